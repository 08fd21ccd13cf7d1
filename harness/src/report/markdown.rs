//! Report folders: every command writes CSVs, plots and a short Markdown report that links
//! them into one folder, and prints where. Every file goes through [`crate::atomic`], so a
//! failed or interrupted run never leaves a corrupt or half-written result.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::atomic::write_atomic;

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

    /// Starts a section: a `##` heading.
    pub fn heading(&mut self, text: &str) {
        println!("\n## {text}");
        if !self.markdown.is_empty() && !self.markdown.ends_with("\n\n") {
            // After a list of files: a blank line ends it.
            self.markdown.push('\n');
        }
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

    /// A plot written by [`super::plot`] as `<stem>.png` and `<stem>.svg`.
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
