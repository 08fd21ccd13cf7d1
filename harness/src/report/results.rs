//! `docs/results.md` written whole from one run of the main job (`harness report --full
//! --results docs/results.md`): the run's `report.md` under a heading that says which
//! command, date and commit it is, its plots copied beside it into `img/`, so that the
//! records quote one run of one commit rather than a patchwork.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result};

use crate::atomic::write_atomic;

/// Where and when a run happened, for the heading.
pub struct Provenance {
    /// The command as a user types it.
    pub command: String,
    /// The run's wall time (s).
    pub seconds: f64,
}

/// The output of `program args` (trimmed), or `None` if it cannot run or fails.
fn output_of(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// The commit of the working directory, marked when the tree differs from it.
fn commit() -> String {
    let Some(head) = output_of("git", &["rev-parse", "--short=10", "HEAD"]) else {
        return "unknown (not a git checkout)".into();
    };
    let dirty = output_of("git", &["status", "--porcelain", "--untracked-files=no"])
        .is_some_and(|s| !s.is_empty());
    if dirty {
        format!("{head} with uncommitted changes")
    } else {
        head
    }
}

/// Rewrites the report's Markdown for a page in another folder: plots point into `img/`
/// (the PNG only), links to the run's other files become their names. Returns the text and
/// the plots to copy.
fn relocate(markdown: &str) -> (String, Vec<String>) {
    let mut plots = Vec::new();
    let mut out = String::new();
    for line in markdown.lines() {
        if let Some(rest) = line.strip_prefix("![") {
            let (caption, target) = rest.split_once("](").unwrap_or((rest, ")"));
            let file = target.trim_end_matches(')').to_string();
            out += &format!("![{caption}](img/{file})\n");
            plots.push(file);
        } else if let Some((kept, _)) = line.split_once(" ([SVG](") {
            out += &format!("{kept}\n");
        } else if let (Some(item), true) = (line.strip_prefix("- "), line.ends_with(')')) {
            let (what, link) = item.split_once(": [").unwrap_or((item, ""));
            let file = link.split_once("](").map_or(link, |(f, _)| f);
            out += &format!("- {what}: `{file}` (in the run's folder)\n");
        } else {
            out += line;
            out.push('\n');
        }
    }
    (out, plots)
}

/// Writes `results` whole from the report at `report_md`: the heading with `provenance`,
/// the date and the commit, then the report's sections, its plots copied to `img/` beside
/// `results`. Every file goes through a temporary file and a rename.
pub fn publish(report_md: &Path, results: &Path, provenance: &Provenance) -> Result<PathBuf> {
    // Read before the plots are copied: they change the tree.
    let commit = commit();
    let markdown = std::fs::read_to_string(report_md)
        .with_context(|| format!("reading {}", report_md.display()))?;
    let body = markdown.split_once("\n\n").map_or("", |(_, b)| b);
    let (body, plots) = relocate(body);
    let folder = results.parent().unwrap_or(Path::new("."));
    let img = folder.join("img");
    std::fs::create_dir_all(&img).with_context(|| format!("creating {}", img.display()))?;
    let from = report_md.parent().unwrap_or(Path::new("."));
    for plot in &plots {
        let bytes = std::fs::read(from.join(plot))
            .with_context(|| format!("reading the plot {}", from.join(plot).display()))?;
        let to = img.join(plot);
        if let Some(folder) = to.parent() {
            std::fs::create_dir_all(folder)
                .with_context(|| format!("creating {}", folder.display()))?;
        }
        write_atomic(&to, &bytes)?;
    }
    let date = output_of("date", &["-u", "+%Y-%m-%d"]).unwrap_or_else(|| "unknown".into());
    let (minutes, seconds) = (
        (provenance.seconds / 60.0).floor(),
        provenance.seconds % 60.0,
    );
    let heading = format!(
        "# Results of the full report\n\nWritten whole by `{}` on {date} at commit {}: {minutes} \
         min {seconds:.0} s of wall time on {} cores. Nothing here is edited by hand; run the \
         command again to renew it. Timings are of that one run (read ratios, not digits); \
         every other number is what the code computes.\n\n",
        provenance.command,
        commit,
        std::thread::available_parallelism().map_or(0, usize::from),
    );
    write_atomic(results, format!("{heading}{body}").as_bytes())?;
    Ok(results.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A report's plots land in `img/` beside the page, their links follow them, the SVG
    /// links and links to the run's files go, and the heading names the command.
    #[test]
    fn a_published_report_points_at_its_copied_plots() {
        let run = tempfile::tempdir().unwrap();
        let md = "# title\n\n## Section\n\n| a |\n|---|\n| 1 |\n\n![Front](pareto.png)\n\n\
                  *Front* ([SVG](pareto.svg))\n\n![Sweep](sweep/metric.png)\n\n\
                  - cases: [cases.csv](cases.csv)\n";
        std::fs::write(run.path().join("report.md"), md).unwrap();
        std::fs::write(run.path().join("pareto.png"), b"png bytes").unwrap();
        // A sweep's plots sit in its own folder of the run (the full report's did not
        // publish: its folder under img/ was not made).
        std::fs::create_dir(run.path().join("sweep")).unwrap();
        std::fs::write(run.path().join("sweep/metric.png"), b"sweep png").unwrap();
        let docs = tempfile::tempdir().unwrap();
        let page = docs.path().join("results.md");
        let provenance = Provenance {
            command: "harness report --full".into(),
            seconds: 125.0,
        };
        publish(&run.path().join("report.md"), &page, &provenance).unwrap();
        let text = std::fs::read_to_string(&page).unwrap();
        assert!(
            text.starts_with(
                "# Results of the full report\n\nWritten whole by `harness report --full` on "
            ),
            "{text}"
        );
        assert!(text.contains("2 min 5 s of wall time"), "{text}");
        assert!(
            text.contains("## Section\n\n| a |\n|---|\n| 1 |\n"),
            "{text}"
        );
        assert!(text.contains("![Front](img/pareto.png)\n"), "{text}");
        assert!(
            text.contains("*Front*\n") && !text.contains("svg"),
            "{text}"
        );
        assert!(
            text.contains("- cases: `cases.csv` (in the run's folder)"),
            "{text}"
        );
        assert!(!text.contains("# title"), "{text}");
        assert_eq!(
            std::fs::read(docs.path().join("img/pareto.png")).unwrap(),
            b"png bytes"
        );
        assert!(text.contains("![Sweep](img/sweep/metric.png)\n"), "{text}");
        assert_eq!(
            std::fs::read(docs.path().join("img/sweep/metric.png")).unwrap(),
            b"sweep png"
        );
        // A plot the report names but the run lacks is an error, and the page is not written.
        std::fs::remove_file(run.path().join("pareto.png")).unwrap();
        let other = docs.path().join("other.md");
        let e = publish(&run.path().join("report.md"), &other, &provenance).unwrap_err();
        assert!(format!("{e:#}").contains("pareto.png"), "{e:#}");
        assert!(!other.exists());
    }
}
