//! Report folders: every command writes CSVs, plots and a short Markdown report that links
//! them into one folder, and prints where. Files are written atomically (a temporary file in
//! the same folder, then a rename), so a failed or interrupted run never leaves a corrupt or
//! half-written result.

use std::fmt::Write as _;
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

/// A report being written: a folder and the Markdown text of `report.md`. Text added to it
/// is echoed to standard output as well, so long commands show where they are.
pub struct Report {
    dir: PathBuf,
    markdown: String,
}

impl Report {
    /// Starts a report in `dir` (created if needed) with a title.
    pub fn create(dir: &Path, title: &str) -> Result<Self> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        println!("# {title}");
        Ok(Self {
            dir: dir.to_path_buf(),
            markdown: format!("# {title}\n\n"),
        })
    }

    /// The report's folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// A file in the report's folder.
    pub fn path(&self, file: &str) -> PathBuf {
        self.dir.join(file)
    }

    pub fn heading(&mut self, text: &str) {
        println!("\n## {text}");
        self.markdown += &format!("## {text}\n\n");
    }

    /// A paragraph.
    pub fn text(&mut self, text: &str) {
        println!("{text}");
        self.markdown += &format!("{text}\n\n");
    }

    /// Preformatted text (the verification reports' tables).
    pub fn verbatim(&mut self, text: &str) {
        print!("{text}");
        self.markdown += &format!("```text\n{text}```\n\n");
    }

    /// A Markdown table.
    pub fn table(&mut self, header: &[&str], rows: &[Vec<String>]) {
        let mut t = format!(
            "| {} |\n|{}\n",
            header.join(" | "),
            "---|".repeat(header.len())
        );
        for r in rows {
            let cells: Vec<String> = r.iter().map(|c| c.replace('|', "\\|")).collect();
            let _ = writeln!(t, "| {} |", cells.join(" | "));
        }
        println!("{t}");
        self.markdown += &t;
        self.markdown += "\n";
    }

    /// A plot written by [`crate::plot`] as `<stem>.png` and `<stem>.svg`.
    pub fn figure(&mut self, caption: &str, stem: &str) {
        println!("figure: {}", self.path(&format!("{stem}.png")).display());
        self.markdown +=
            &format!("![{caption}]({stem}.png)\n\n*{caption}* ([SVG]({stem}.svg))\n\n");
    }

    /// A link to a file in the folder.
    pub fn file(&mut self, what: &str, file: &str) {
        println!("{what}: {}", self.path(file).display());
        self.markdown += &format!("- {what}: [{file}]({file})\n");
    }

    /// Writes `report.md` and returns its path.
    pub fn finish(self) -> Result<PathBuf> {
        let path = self.dir.join("report.md");
        write_atomic(&path, self.markdown.as_bytes())?;
        Ok(path)
    }
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
