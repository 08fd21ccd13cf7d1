//! Writes abdomen-fmi2.fmu, abdomen-fmi3.fmu, cutblock-fmi2.fmu and cutblock-fmi3.fmu into
//! `target/fmu/`.
//!
//! Run: `cargo run --release -p fmu --bin bundle` (cargo builds the shared library of the
//! `fmu` crate alongside this binary; the bundler takes it from the same folder), or
//! `bundle --library PATH` with a library built elsewhere — `fmu/bundle.sh` passes the one
//! built against glibc 2.28.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let exe = std::env::current_exe().unwrap_or_default();
    let dir = exe.parent().map(PathBuf::from).unwrap_or_default();
    let args: Vec<String> = std::env::args().skip(1).collect();
    let library = match args.as_slice() {
        [] => dir.join(format!(
            "{}fmu{}",
            std::env::consts::DLL_PREFIX,
            std::env::consts::DLL_SUFFIX
        )),
        [flag, path] if flag == "--library" => PathBuf::from(path),
        _ => {
            eprintln!("usage: bundle [--library PATH-TO-libfmu.so]");
            return ExitCode::FAILURE;
        }
    };
    let out = dir
        .parent()
        .map_or_else(|| PathBuf::from("target/fmu"), |target| target.join("fmu"));
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
