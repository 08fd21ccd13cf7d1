//! tissuefmu harness: the command-line front end. Every command writes a report folder (CSVs,
//! plots as PNG and SVG, VTU fields, `report.md` linking them) and prints its path. Without a
//! command it runs `report`, everything on built-in defaults (the README's main job).

mod abdomen_report;
mod core_report;
mod cutblock_report;
mod fields_report;
mod identify_report;
mod speed_error_report;
mod sweep_report;

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::{Parser, Subcommand};
use harness::experiment::Experiment;
use harness::report::Report;
use identify_report::Data;

/// The shipped experiments and data, in the repository this harness was built from.
fn experiments() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments");
    dir.canonicalize().unwrap_or(dir)
}

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
    /// Fits E (and ν, from laser profiles) of the cut block to measurements
    Identify {
        /// Folder with force_displacement_<set>.csv and profile_<set>_x25/50/75.csv
        /// [default: the shipped experiments/data/cutblock]
        #[arg(long)]
        data: Option<PathBuf>,
        /// Name of the measurement set in the folder
        #[arg(long, default_value = "A")]
        set: String,
        /// A force–displacement CSV (displacement mm, force N) to fit instead of a set; needs --nu
        #[arg(long, conflicts_with_all = ["data", "set"], requires = "nu")]
        forces: Option<PathBuf>,
        /// Fix Poisson's ratio instead of fitting it to the profiles
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
}

fn verify(report: &mut Report) -> Result<()> {
    report.heading("Verification");
    for section in [core_report::run, cutblock_report::run, abdomen_report::run] {
        let mut text = String::new();
        section(&mut text)?;
        report.verbatim(&text);
    }
    Ok(())
}

fn sweep(
    path: &Path,
    out: Option<PathBuf>,
    jobs: Option<usize>,
    plan_only: bool,
) -> Result<PathBuf> {
    let mut e = Experiment::load(path)?;
    if let Some(j) = jobs {
        e.jobs = j;
    }
    let dir = out.unwrap_or_else(|| Path::new("report").join(&e.name));
    if plan_only {
        harness::sweep::prepare(&e, &dir)?;
        return Ok(dir.join("plan.json"));
    }
    Ok(sweep_report::run(&e, &dir)?.0)
}

/// The shipped sweeps the default report runs, with the parameters whose plots it shows
/// inline (the rest are in each sweep's own report).
const SHIPPED_SWEEPS: [(&str, &[&str]); 2] = [
    ("pelvis_sweep", &["configuration", "anatomy.outlet"]),
    ("cutblock_sweep", &["cut_depth"]),
];

/// Runs a shipped sweep into a subfolder and summarizes it in `report`.
fn shipped_sweep(report: &mut Report, name: &str, shown: &[&str]) -> Result<()> {
    let e = Experiment::load(&experiments().join(format!("{name}.toml")))?;
    report.heading(&format!("Sweep `{name}` ({} cases)", e.cases.len()));
    report.text(&e.description);
    let (_, correlations) = sweep_report::run(&e, &report.path(name))?;
    report.text(&format!(
        "Full sweep report: [{name}/report.md]({name}/report.md)."
    ));
    for parameter in shown {
        report.figure(
            &format!("Peak {} against {parameter}", e.metric),
            &format!("{name}/{}", sweep_report::plot_stem(parameter)),
        );
    }
    report.table(
        &["parameter", "cases of", "cases", "Pearson r with the peak"],
        &correlations,
    );
    Ok(())
}

fn default_report(out: &Path) -> Result<PathBuf> {
    let mut report = Report::create(out, "tissuefmu report on built-in defaults")?;
    verify(&mut report)?;
    let data = experiments().join("data/cutblock");
    identify_report::run(
        &mut report,
        Data::Set {
            dir: &data,
            set: "A",
        },
        None,
    )?;
    speed_error_report::run(&mut report)?;
    for (name, shown) in SHIPPED_SWEEPS {
        shipped_sweep(&mut report, name, shown)?;
    }
    fields_report::run(&mut report)?;
    report.finish()
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(path) => {
            println!("\nwritten to {}", path.display());
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<PathBuf> {
    let path = match cli.command.unwrap_or(Command::Report {
        out: PathBuf::from("report/default"),
    }) {
        Command::Report { out } => default_report(&out)?,
        Command::Sweep {
            experiment,
            out,
            jobs,
            plan_only,
        } => sweep(&experiment, out, jobs, plan_only)?,
        Command::Identify {
            data,
            set,
            forces,
            nu,
            out,
        } => {
            let mut r = Report::create(&out, "Material identification")?;
            let dir = data.unwrap_or_else(|| experiments().join("data/cutblock"));
            let what = match &forces {
                Some(path) => Data::Forces(path),
                None => Data::Set {
                    dir: &dir,
                    set: &set,
                },
            };
            identify_report::run(&mut r, what, nu)?;
            r.finish()?
        }
        Command::SpeedError { out } => {
            let mut r = Report::create(&out, "Speed versus error")?;
            speed_error_report::run(&mut r)?;
            r.finish()?
        }
        Command::Verify { out } => {
            let mut r = Report::create(&out, "Verification")?;
            verify(&mut r)?;
            r.finish()?
        }
        Command::Fields { out } => {
            let mut r = Report::create(&out, "Fields")?;
            fields_report::run(&mut r)?;
            r.finish()?
        }
    };
    Ok(path)
}
