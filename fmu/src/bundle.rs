//! Writes `<model>-fmi2.fmu` and `<model>-fmi3.fmu` archives: model description, the shared
//! library under `binaries/<platform>/<model>.so`, and `resources/` with the model's
//! defaults and (for the abdomen) copies of the shipped pelvis configurations the library
//! carries, for users to read and start their own from. Each archive is written
//! to a temporary file and renamed into place, so a failed run leaves no half-written FMU.

use std::io::Write;
use std::path::{Path, PathBuf};

use models::scene::Start;
use zip::write::SimpleFileOptions;

use crate::exports::{Export, Version, EXPORTS};
use crate::xml;

/// Binary folder name for this platform (FMI 2: `linux64`; FMI 3: `x86_64-linux`).
fn platform(version: Version) -> Result<&'static str, String> {
    match (version, std::env::consts::OS, std::env::consts::ARCH) {
        (Version::Fmi2, "linux", "x86_64") => Ok("linux64"),
        (Version::Fmi3, "linux", "x86_64") => Ok("x86_64-linux"),
        (Version::Fmi2, "linux", "aarch64") => Ok("linux64"),
        (Version::Fmi3, "linux", "aarch64") => Ok("aarch64-linux"),
        (_, os, arch) => Err(format!("no FMI platform name known for {arch}-{os}")),
    }
}

/// The defaults of a model's parameters and inputs, as a readable TOML-like listing.
fn defaults(model: &Export) -> String {
    let scene = (model.create)();
    let mut s = format!(
        "# Start values of `{}` (generated from its variable table)\n",
        model.identifier
    );
    for v in scene.variables() {
        match &v.start {
            Start::Real(x) => s += &format!("{} = {x:?}  # {}\n", v.name, v.unit),
            Start::String(x) => s += &format!("{} = {x:?}\n", v.name),
            Start::None => {}
        }
    }
    s
}

/// Writes one archive; returns its path.
pub fn write(
    model: &Export,
    version: Version,
    library: &Path,
    out_dir: &Path,
) -> Result<PathBuf, String> {
    let err = |what: &str, e: &dyn std::fmt::Display| format!("{what}: {e}");
    let binary =
        std::fs::read(library).map_err(|e| err(&format!("reading {}", library.display()), &e))?;
    let description = match version {
        Version::Fmi2 => xml::fmi2(model),
        Version::Fmi3 => xml::fmi3(model),
    };
    std::fs::create_dir_all(out_dir).map_err(|e| err("creating the output folder", &e))?;
    let path = out_dir.join(format!("{}-{}.fmu", model.identifier, version.tag()));
    let partial = path.with_extension("fmu.partial");
    let file = std::fs::File::create(&partial)
        .map_err(|e| err(&format!("creating {}", partial.display()), &e))?;
    let mut zip = zip::ZipWriter::new(file);
    let options = SimpleFileOptions::default();
    let mut add = |name: &str, bytes: &[u8]| -> Result<(), String> {
        zip.start_file(name, options).map_err(|e| err(name, &e))?;
        zip.write_all(bytes).map_err(|e| err(name, &e))
    };
    add("modelDescription.xml", description.as_bytes())?;
    add(
        &format!("binaries/{}/{}.so", platform(version)?, model.identifier),
        &binary,
    )?;
    add("resources/defaults.toml", defaults(model).as_bytes())?;
    if model.identifier == "abdomen" {
        for (name, text) in models::scene::abdomen::config::SHIPPED {
            add(&format!("resources/pelvis/{name}.toml"), text.as_bytes())?;
        }
    }
    zip.finish().map_err(|e| err("finishing the archive", &e))?;
    std::fs::rename(&partial, &path).map_err(|e| err("renaming the archive into place", &e))?;
    Ok(path)
}

/// Writes every model in both versions.
pub fn write_all(library: &Path, out_dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    for model in &EXPORTS {
        for version in [Version::Fmi2, Version::Fmi3] {
            written.push(write(model, version, library, out_dir)?);
        }
    }
    Ok(written)
}
