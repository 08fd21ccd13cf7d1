//! Files written atomically: a temporary file in the same folder, then a rename, so that a
//! failed or interrupted run never leaves a corrupt or half-written file behind.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// Writes `bytes` to `path` through a temporary file and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temporary(path);
    std::fs::write(&tmp, bytes).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))
}

/// A temporary name next to `path` that keeps its extension (plot backends pick the format
/// from it): `a/b.png` → `a/.b.tmp.png`.
pub fn temporary(path: &Path) -> PathBuf {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let tmp = match name.rsplit_once('.') {
        Some((stem, ext)) => format!(".{stem}.tmp.{ext}"),
        None => format!(".{name}.tmp"),
    };
    path.with_file_name(tmp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_writes_leave_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        write_atomic(&p, b"x\n").unwrap();
        write_atomic(&p, b"y\n").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"y\n");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1);
        assert_eq!(temporary(Path::new("r/p.png")), Path::new("r/.p.tmp.png"));
    }
}
