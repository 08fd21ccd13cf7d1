//! tissuefmu harness: the command-line front end. It parses the command and dispatches to
//! the library ([`harness::report`]); every command but `simulate` and `describe` writes a
//! report folder (CSVs, plots as PNG and SVG, VTU fields, `report.md` linking them) and
//! prints its path. Without a command it prints its help.

use std::path::PathBuf;

use anyhow::Result;
use clap::{CommandFactory, Parser, Subcommand};
use harness::report::{
    self, blade_path, cut_speed_error, fields, identification, model_order, series, speed_error,
    sweep, variables, verification, Depth,
};
use harness::studies::identify::ModelForm;
use harness::studies::{cut_speed_error as cut_study, measurements, peer};

#[derive(Parser)]
#[command(
    name = "harness",
    version,
    about = "Experiments, sweeps, identification and reports for the tissuefmu scenes",
    after_help = "Start with `harness report` (a few minutes; `--full` for the converged \
                  studies). Documentation: docs/user-guide.md"
)]
struct Cli {
    /// Threads for the work that runs in parallel (sweep cases, fits, the scenes' assembly
    /// and factorization) [default: one per core; a sweep file's `jobs` unless given]
    #[arg(long, global = true)]
    jobs: Option<usize>,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Everything on built-in defaults, each capability once (quick: a few minutes), or the
    /// converged studies with --full: verification, identification on the shipped data,
    /// speed versus error, the shipped sweeps (pelvis, cut block), fields
    Report {
        /// The converged studies: references, full speed–error fronts, every
        /// identification, the pelvis sweep in four model forms (tens of minutes on 2
        /// cores: docs/results.md gives the time of the last run)
        #[arg(long)]
        full: bool,
        #[arg(long, default_value = "report/default")]
        out: PathBuf,
        /// Also write this page whole from the run (the report under a heading with the
        /// command, date and commit; its plots copied to `img/` beside it): how
        /// docs/results.md is made
        #[arg(long, requires = "full")]
        results: Option<PathBuf>,
    },
    /// Runs (or resumes) the sweep of an experiment file
    Sweep {
        /// The experiment: a TOML file, or the name of a shipped one (pelvis_sweep,
        /// cutblock_sweep, and the clinical load presets clinical_rest, clinical_cough,
        /// clinical_valsalva, clinical_bear_down)
        experiment: PathBuf,
        /// Output folder [default: report/<experiment name>]; re-running resumes it
        #[arg(long)]
        out: Option<PathBuf>,
        /// Only write the plan (plan.json, for harness/python/dask_sweep.py); run nothing
        #[arg(long)]
        plan_only: bool,
    },
    /// Fits E and ν of a cut-block model to a measurement set (forces, laser profiles);
    /// writes report.md, plots and identify.json
    Identify {
        /// Folder with specimen_<set>.toml, force_displacement_<set>.csv and (optional) one
        /// profile_<set>_x<X>.csv per scan line of the specimen [default: the shipped sets
        /// A and C]
        #[arg(long)]
        data: Option<PathBuf>,
        /// Name of the measurement set in the folder; several (`--set A,C`) are a batch:
        /// one fit each, side by side in one report and one table
        #[arg(long, default_value = "A", value_delimiter = ',', num_args = 1..)]
        set: Vec<String>,
        /// Material law of the model: linear, neo-hookean or stvk
        #[arg(long, default_value = "neo-hookean")]
        material: String,
        /// Element of the model: tet4 or tet10
        #[arg(long, default_value = "tet10")]
        element: String,
        /// Fix Poisson's ratio instead of fitting it (needed when the set has no profiles)
        #[arg(long)]
        nu: Option<f64>,
        /// Measure the mesh's share of the intervals: the fit again on the specimen's cells
        /// × 1.5 and × 2, extrapolated (neo-Hookean tet10 on the shipped sets' 6 × 16 × 14
        /// cells: about 15 min and 3.4 GB; the shipped sets' are stored)
        #[arg(long)]
        discretization: bool,
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
        /// Where the incision ends (x, mm; 100: the seed's full cut)
        #[arg(long, default_value_t = cut_study::FULL_CUT)]
        front: f64,
        /// The reference's meshes: factors on its cells (one, three or four, increasing;
        /// default 0.5,1,1.5,2 at the full cut, 0.5,1,1.5 at a partial cut)
        #[arg(long, value_delimiter = ',')]
        reference_refine: Option<Vec<f64>>,
    },
    /// The blade crossing the pulled cut block in 1 mm steps on 1× and 2× cells: reaction,
    /// opening and lift against the blade, their difference, CSV and plot
    BladePath {
        #[arg(long, default_value = "report/blade_path")]
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
    /// The variable reference of a scene (name, causality, variability, type, unit, start,
    /// range, description), to standard output
    Describe {
        /// The scene: abdomen or cutblock
        scene: String,
        #[arg(long, value_enum, default_value = "text")]
        format: variables::Format,
    },
    /// Model orders compared: the shipped configurations in full and hyper-reduced order at
    /// finite strain and modal order at small strain (times, errors against full finite
    /// strain, rankings, error indicators); the shipped pelvis sweep in those and in full
    /// order at small strain (wall times, errors, rankings)
    ModelOrder {
        #[arg(long, default_value = "report/model_order")]
        out: PathBuf,
        /// Only the configurations, as the quick report runs them (the sweep takes minutes)
        #[arg(long)]
        quick: bool,
    },
    /// Pelvis rankings with their confidence: samples of the uncertain tissue properties,
    /// sections, wall setting and clinical load, each run on the five shipped
    /// configurations; rankings.csv gives, for each pair, the fraction of samples in which
    /// the first loads the pelvic floor more (by floor_stress_mean and floor_stress_max)
    Rankings {
        /// Samples (each runs on the five configurations), at least 1
        #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(1..))]
        samples: u64,
        #[arg(long, default_value = "report/rankings")]
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
    let Some(command) = cli.command else {
        Cli::command().print_help()?;
        return Ok(None);
    };
    if let Some(jobs) = cli.jobs {
        anyhow::ensure!(jobs > 0, "--jobs {jobs}: give at least one thread");
        rayon::ThreadPoolBuilder::new()
            .num_threads(jobs)
            .build_global()?;
    }
    let path = match command {
        Command::Report { full, out, results } => {
            let depth = if full { Depth::Full } else { Depth::Quick };
            let start = std::time::Instant::now();
            let md = report::default::run(&out, depth)?;
            match results {
                Some(page) => {
                    let provenance = report::results::Provenance {
                        command: format!(
                            "harness report --full --out {} --results {}",
                            out.display(),
                            page.display()
                        ),
                        seconds: start.elapsed().as_secs_f64(),
                    };
                    report::results::publish(&md, &page, &provenance)?
                }
                None => md,
            }
        }
        Command::Sweep {
            experiment,
            out,
            plan_only,
        } => sweep::command(&experiment, out, cli.jobs, plan_only)?,
        Command::Identify {
            data,
            set,
            material,
            element,
            nu,
            discretization,
            out,
        } => {
            let model = ModelForm::parse(&material, &element)?;
            let jobs = set
                .into_iter()
                .map(|set| identification::Job {
                    data: measurements::source(data.as_deref()),
                    set,
                    model,
                    nu,
                    discretization,
                })
                .collect();
            identification::command(jobs, &out)?
        }
        Command::SpeedError { out } => report::write(
            &out,
            "Speed versus error",
            speed_error::section,
            Depth::Full,
        )?,
        Command::CutSpeedError {
            out,
            front,
            reference_refine,
        } => {
            let refine =
                reference_refine.unwrap_or_else(|| cut_study::reference_refine(front).to_vec());
            let study = cut_study::Study::at(front, &refine)?;
            let mut report = report::Report::create(&out, "Speed versus error, cut block")?;
            cut_speed_error::study_section(&mut report, &study, Depth::Full)?;
            report.finish()?
        }
        Command::BladePath { out } => {
            report::write(&out, "Blade path", blade_path::section, Depth::Full)?
        }
        Command::Verify { out } => {
            report::write(&out, "Verification", verification::section, Depth::Full)?
        }
        Command::Fields { out } => report::write(&out, "Fields", fields::section, Depth::Full)?,
        Command::ModelOrder { out, quick } => report::write(
            &out,
            "Model orders",
            model_order::section,
            if quick { Depth::Quick } else { Depth::Full },
        )?,
        Command::Rankings { samples, out } => {
            let mut report = report::Report::create(&out, "Pelvis rankings")?;
            report::rankings::rankings(&mut report, samples as usize)?;
            report.finish()?
        }
        Command::Describe { scene, format } => {
            print!("{}", variables::describe(&scene, format)?);
            return Ok(None);
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
