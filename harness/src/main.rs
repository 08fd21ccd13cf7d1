//! tissuefmu harness: the command-line front end. It parses the command and dispatches to
//! the library ([`harness::report`]); every command but `simulate` writes a report folder
//! (CSVs, plots as PNG and SVG, VTU fields, `report.md` linking them) and prints its path.
//! Without a command it runs `report`, everything on built-in defaults (the README's main
//! job).

use std::path::PathBuf;

use anyhow::Result;
use clap::{Parser, Subcommand};
use harness::report::{
    self, cut_speed_error, fields, identification, model_order, series, speed_error, sweep,
    verification,
};
use harness::studies::identify::Model;
use harness::studies::peer;

#[derive(Parser)]
#[command(
    name = "harness",
    version,
    about = "Experiments, sweeps, identification and reports for the tissuefmu scenes"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Everything on built-in defaults: verification, identification on the shipped data,
    /// speed versus error, the shipped sweeps (pelvis, cut block), fields
    Report {
        #[arg(long, default_value = "report/default")]
        out: PathBuf,
    },
    /// Runs (or resumes) the sweep of an experiment file
    Sweep {
        /// The experiment (TOML), e.g. experiments/pelvis_sweep.toml
        experiment: PathBuf,
        /// Output folder [default: report/<experiment name>]; re-running resumes it
        #[arg(long)]
        out: Option<PathBuf>,
        /// Cases in parallel, overriding the file's `jobs`
        #[arg(long)]
        jobs: Option<usize>,
        /// Only write the plan (plan.json, for harness/python/dask_sweep.py); run nothing
        #[arg(long)]
        plan_only: bool,
    },
    /// Fits E and ν of a cut-block model to a measurement set (forces, laser profiles)
    Identify {
        /// Folder with specimen_<set>.toml, force_displacement_<set>.csv and (optional)
        /// profile_<set>_x25/50/75.csv [default: the shipped experiments/data/cutblock]
        #[arg(long)]
        data: Option<PathBuf>,
        /// Name of the measurement set in the folder
        #[arg(long, default_value = "A")]
        set: String,
        /// Material law of the model: linear, neo-hookean or stvk
        #[arg(long, default_value = "neo-hookean")]
        material: String,
        /// Element of the model: tet4 or tet10
        #[arg(long, default_value = "tet10")]
        element: String,
        /// Fix Poisson's ratio instead of fitting it (needed when the set has no profiles)
        #[arg(long)]
        nu: Option<f64>,
        #[arg(long, default_value = "report/identify")]
        out: PathBuf,
    },
    /// Speed versus error of the abdomen and the stability table
    SpeedError {
        #[arg(long, default_value = "report/speed_error")]
        out: PathBuf,
    },
    /// Speed versus error of the cut block's models (law × element × mesh), Pareto plot
    CutSpeedError {
        #[arg(long, default_value = "report/cut_speed_error")]
        out: PathBuf,
    },
    /// Verification of the FE core and both scenes against analytical and seed results
    Verify {
        #[arg(long, default_value = "report/verify")]
        out: PathBuf,
    },
    /// Stress map of the abdomen and VTU fields of both scenes
    Fields {
        #[arg(long, default_value = "report/fields")]
        out: PathBuf,
    },
    /// The shipped pelvis sweep in full and modal order: wall times and peak differences
    ModelOrder {
        #[arg(long, default_value = "report/model_order")]
        out: PathBuf,
    },
    /// The default abdomen's matrices, load and a Houbolt run for the peer benchmark
    /// (benches/peer/run.sh), with this project's step, solve and factorization times on them
    PeerExport {
        #[arg(long, default_value = "target/peer")]
        out: PathBuf,
        /// Houbolt steps of the exported run (and solves timed)
        #[arg(long, default_value_t = 2000)]
        steps: usize,
    },
    /// One run of a scene in process, as a CSV of time and outputs (to standard output
    /// unless --out); inputs are sampled at the start of each communication step and held
    Simulate {
        /// The scene: abdomen or cutblock
        scene: String,
        /// Start time (s)
        #[arg(long, default_value_t = 0.0)]
        start_time: f64,
        /// Stop time (s)
        #[arg(long)]
        stop_time: f64,
        /// Communication step (s)
        #[arg(long)]
        step: f64,
        /// A parameter before initialization, name=value (repeatable)
        #[arg(long)]
        set: Vec<String>,
        /// A CSV `time,<input>,…` of piecewise-linear inputs
        #[arg(long)]
        inputs: Option<PathBuf>,
        /// The outputs to record, comma-separated (arrays give one column per element)
        #[arg(long, value_delimiter = ',', required = true)]
        record: Vec<String>,
        /// The CSV file to write
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(Some(path)) => {
            println!("\nwritten to {}", path.display());
            std::process::ExitCode::SUCCESS
        }
        Ok(None) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<Option<PathBuf>> {
    let command = cli.command.unwrap_or(Command::Report {
        out: PathBuf::from("report/default"),
    });
    let path = match command {
        Command::Report { out } => report::default::run(&out)?,
        Command::Sweep {
            experiment,
            out,
            jobs,
            plan_only,
        } => sweep::command(&experiment, out, jobs, plan_only)?,
        Command::Identify {
            data,
            set,
            material,
            element,
            nu,
            out,
        } => identification::command(
            identification::Job {
                dir: data.unwrap_or_else(identification::shipped_data),
                set,
                model: Model::new(&material, &element),
                nu,
            },
            &out,
        )?,
        Command::SpeedError { out } => {
            report::write(&out, "Speed versus error", speed_error::section)?
        }
        Command::CutSpeedError { out } => report::write(
            &out,
            "Speed versus error, cut block",
            cut_speed_error::section,
        )?,
        Command::Verify { out } => report::write(&out, "Verification", verification::section)?,
        Command::Fields { out } => report::write(&out, "Fields", fields::section)?,
        Command::ModelOrder { out } => {
            report::write(&out, "Full against modal order", model_order::section)?
        }
        Command::PeerExport { out, steps } => {
            let t = peer::export(&out, steps)?;
            println!(
                "Houbolt step {:.1} µs, solve {:.1} µs, factorization {:.2} ms (medians)",
                t.step * 1e6,
                t.solve * 1e6,
                t.factor * 1e3
            );
            out
        }
        Command::Simulate {
            scene,
            start_time,
            stop_time,
            step,
            set,
            inputs,
            record,
            out,
        } => {
            return series::command(&series::Request {
                scene: &scene,
                start_time,
                stop_time,
                step,
                set: &set,
                inputs: inputs.as_deref(),
                record: &record,
                out: out.as_deref(),
            })
        }
    };
    Ok(Some(path))
}
