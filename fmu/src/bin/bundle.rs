//! Writes abdomen-fmi2.fmu, abdomen-fmi3.fmu, cutblock-fmi2.fmu and cutblock-fmi3.fmu into
//! `target/fmu/`.
//!
//! Run: `cargo run --release -p fmu --bin bundle` (cargo builds the shared library of the
//! `fmu` crate alongside this binary; the bundler takes it from the same folder), or
//! `bundle --library PATH` with a library built elsewhere. `--out DIR` writes the archives
//! there instead of `fmu/` beside the binary's profile folder (`fmu/bundle.sh` and
//! `tests/run.sh` run the bundler built against glibc 2.28, from
//! `target/x86_64-unknown-linux-gnu/release/`, into `target/fmu/`).

use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "usage: bundle [--library PATH-TO-libfmu.so] [--out DIR]";

fn main() -> ExitCode {
    let exe = std::env::current_exe().unwrap_or_default();
    let dir = exe.parent().map(PathBuf::from).unwrap_or_default();
    let mut library = dir.join(format!(
        "{}fmu{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ));
    let mut out = dir
        .parent()
        .map_or_else(|| PathBuf::from("target/fmu"), |target| target.join("fmu"));
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let slot = match flag.as_str() {
            "--library" => &mut library,
            "--out" => &mut out,
            _ => {
                eprintln!("bundle: unknown argument `{flag}`\n{USAGE}");
                return ExitCode::FAILURE;
            }
        };
        let Some(value) = args.next() else {
            eprintln!("bundle: `{flag}` needs a path\n{USAGE}");
            return ExitCode::FAILURE;
        };
        *slot = PathBuf::from(value);
    }
    match fmu::bundle::write_all(&library, &out) {
        Ok(paths) => {
            for p in paths {
                println!("wrote {}", p.display());
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("bundle: {e}");
            ExitCode::FAILURE
        }
    }
}
