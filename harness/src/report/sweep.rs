//! The sweep section: runs (or resumes) the sweep in its folder, then writes the case table,
//! the peak of the experiment's metric against each varied parameter (with the correlation
//! over the cases that vary it) and the metric's time histories; the `sweep` command and the
//! shipped sweeps of the default report.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::Report;
use crate::sweep::{runner, CaseResult, Design, Experiment, Outcome, Series, Value};

/// The unit of a parameter or output, from the scene's table or its generator parameters.
fn unit(e: &Experiment, name: &str) -> String {
    let Ok(scene) = models::scene::create(&e.scene) else {
        return "-".into();
    };
    let table = scene
        .variables()
        .iter()
        .find(|v| v.name == name)
        .map(|v| v.unit);
    let generators = scene.generator_parameters();
    table
        .or_else(|| generators.iter().find(|g| g.name == name).map(|g| g.unit))
        .filter(|u| !u.is_empty() && *u != "1")
        .unwrap_or("-")
        .into()
}

/// The `sweep` command: runs (or resumes) an experiment's sweep into `out` (default
/// `report/<name>`), or with `plan_only` only writes its plan; returns the path written.
pub fn command(
    path: &Path,
    out: Option<PathBuf>,
    jobs: Option<usize>,
    plan_only: bool,
) -> Result<PathBuf> {
    let mut e = Experiment::open(path)?;
    if let Some(j) = jobs {
        e.jobs = j;
    }
    let dir = out.unwrap_or_else(|| Path::new("report").join(&e.name));
    if plan_only {
        runner::prepare(&e, &dir)?;
        return Ok(dir.join("plan.json"));
    }
    Ok(sweep(&e, &dir)?.0)
}

/// Runs a shipped sweep ([`Experiment::shipped`]) into a subfolder of `report` and
/// summarizes it there, with the plots of the parameters in `shown` inline. With `thin` =
/// (samples, levels), the quick report's version of it: its Latin hypercubes drawn anew
/// with that many samples and its grids at that many levels ([`Experiment::thinned`]), into
/// a folder of their own.
pub fn shipped(
    report: &mut Report,
    name: &str,
    shown: &[&str],
    thin: Option<(usize, usize)>,
) -> Result<()> {
    let shipped = Experiment::shipped(name)?;
    let total = shipped.cases.len();
    let (e, quick) = match thin {
        Some((samples, levels)) => {
            let e = shipped.thinned(samples, levels)?;
            let note = format!(
                "Quick: `{name}` with its Latin hypercubes drawn anew with at most {samples} \
                 samples over the same ranges and its grids at {levels} levels, {} cases instead \
                 of its {total}; `--full` runs them all.",
                e.cases.len()
            );
            (e, Some(note))
        }
        None => (shipped, None),
    };
    report.heading(&format!("Sweep `{}` ({} cases)", e.name, e.cases.len()));
    report.text(&e.description);
    if let Some(note) = quick {
        report.text(&note);
    }
    let dir = &e.name;
    let (_, correlations) = sweep(&e, &report.path(dir))?;
    report.text(&format!(
        "Full sweep report: [{dir}/report.md]({dir}/report.md)."
    ));
    for parameter in shown {
        report.figure(
            &format!("Peak {} against {parameter}", e.metric),
            &format!("{dir}/{}", plot_stem(parameter)),
        );
    }
    report.table(
        &["parameter", "cases of", "cases", "Pearson r with the peak"],
        &correlations,
    );
    Ok(())
}

/// The file stem of the plot of the metric against a parameter.
pub fn plot_stem(parameter: &str) -> String {
    format!("metric_vs_{}", parameter.replace('.', "_"))
}

/// Pearson's correlation coefficient.
fn correlation(p: &[(f64, f64)]) -> f64 {
    let n = p.len() as f64;
    let (mx, my) = (
        p.iter().map(|q| q.0).sum::<f64>() / n,
        p.iter().map(|q| q.1).sum::<f64>() / n,
    );
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (x, y) in p {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx) * (x - mx);
        syy += (y - my) * (y - my);
    }
    sxy / (sxx * syy).sqrt()
}

/// Runs the sweep into `dir` and writes its report there; returns the report's path and one
/// line per parameter (its correlation with the metric) for an enclosing report.
pub fn sweep(e: &Experiment, dir: &Path) -> Result<(PathBuf, Vec<Vec<String>>)> {
    let mut report = Report::create(dir, &format!("Sweep `{}`", e.name))?;
    if !e.description.is_empty() {
        report.text(&e.description);
    }
    let s = runner::run(e, dir)?;
    let failed = s
        .results
        .iter()
        .filter(|r| matches!(r.outcome, Outcome::Failed(_)))
        .count();
    report.text(&format!(
        "{} cases ({} run now, {} finished earlier), {failed} failed; {:.1} s wall time; backend {:?}, \
         {} s simulated at a {} s communication step.",
        s.results.len(),
        s.ran,
        s.results.len() - s.ran,
        s.seconds,
        e.backend,
        e.stop_time,
        e.step
    ));
    let j = e.record.iter().position(|r| *r == e.metric).unwrap_or(0);
    let metric_unit = unit(e, &e.metric);
    let metric_label = format!("peak {} ({metric_unit})", e.metric);
    let varied = e.varied();
    let mut header: Vec<&str> = vec!["case"];
    header.extend(varied.iter().map(String::as_str));
    header.push(&metric_label);
    header.push("status");
    let rows: Vec<Vec<String>> = s.results.iter().map(|r| case_row(r, &varied, j)).collect();
    report.table(&header, &rows);
    let mut correlations = Vec::new();
    for name in &varied {
        correlations.extend(parameter_plot(
            &mut report,
            e,
            &s.results,
            name,
            j,
            &metric_label,
        )?);
    }
    if !correlations.is_empty() {
        report.text(
            "Correlation of the metric's peak with each numeric parameter, per group of cases that \
             varies it (in a Latin hypercube the other parameters vary too):",
        );
        report.table(
            &["parameter", "cases of", "cases", "Pearson r"],
            &correlations,
        );
    }
    histories(&mut report, e, &s.results, &metric_unit)?;
    report.file("one row per case", "summary.csv");
    report.file("the case plan", "plan.csv");
    report.file(
        "resolved settings per case (the Dask runner reads it)",
        "plan.json",
    );
    report.file("time histories, one file per case", "cases");
    Ok((report.finish()?, correlations))
}

fn case_row(r: &CaseResult, varied: &[String], j: usize) -> Vec<String> {
    let mut row = vec![r.id.to_string()];
    row.extend(varied.iter().map(|k| {
        r.values.get(k).map_or(String::new(), |v| match v {
            Value::Real(x) => format!("{x:.4}"),
            Value::Text(t) => t.clone(),
        })
    }));
    match &r.outcome {
        Outcome::Finished { .. } => {
            row.push(format!("{:.5}", r.peak(j).unwrap_or(f64::NAN)));
            row.push("finished".into());
        }
        Outcome::Failed(message) => {
            row.push(String::new());
            row.push(format!("failed: {message}"));
        }
    }
    row
}

/// Cases of one curve: a `[[sweep]]` block and, for lists and grids, one combination of
/// the values of its other parameters.
struct Group {
    block: usize,
    design: Design,
    others: String,
    points: Vec<(f64, f64)>,
}

impl Group {
    fn name(&self) -> String {
        let mut name = format!("sweep[{}], {:?}", self.block, self.design);
        if !self.others.is_empty() {
            name += &format!(", {}", self.others);
        }
        name
    }
}

/// The other values of a list or grid case, as `a=1, b=x` (empty for a Latin hypercube,
/// whose other values all differ).
fn others(r: &CaseResult, name: &str) -> String {
    if r.design == Design::LatinHypercube {
        return String::new();
    }
    r.values
        .iter()
        .filter(|(k, _)| k.as_str() != name)
        .map(|(k, v)| format!("{k}={v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Plots the metric's peak against one parameter, one curve per [`Group`] (points joined
/// for lists and grids, scattered for Latin hypercubes); returns one correlation line per
/// group with numeric values.
fn parameter_plot(
    report: &mut Report,
    e: &Experiment,
    results: &[CaseResult],
    name: &str,
    j: usize,
    metric_label: &str,
) -> Result<Vec<Vec<String>>> {
    let mut categories: Vec<String> = Vec::new();
    let mut groups: Vec<Group> = Vec::new();
    for r in results {
        let (Some(v), Some(y)) = (r.values.get(name), r.peak(j)) else {
            continue;
        };
        let x = match v {
            Value::Real(x) => *x,
            Value::Text(t) => {
                if !categories.contains(t) {
                    categories.push(t.clone());
                }
                categories.iter().position(|c| c == t).unwrap_or(0) as f64
            }
        };
        let others = others(r, name);
        match groups
            .iter_mut()
            .find(|g| g.block == r.block && g.others == others)
        {
            Some(g) => g.points.push((x, y)),
            None => groups.push(Group {
                block: r.block,
                design: r.design,
                others,
                points: vec![(x, y)],
            }),
        }
    }
    if groups.is_empty() {
        return Ok(Vec::new());
    }
    let numeric = categories.is_empty();
    let mut curves = Vec::new();
    let mut lines = Vec::new();
    for (k, mut g) in groups.into_iter().enumerate() {
        let mark = if g.design == Design::LatinHypercube {
            Mark::Dots
        } else {
            g.points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Mark::LineDots
        };
        if numeric && g.points.len() > 2 {
            lines.push(vec![
                name.to_string(),
                g.name(),
                g.points.len().to_string(),
                format!("{:+.3}", correlation(&g.points)),
            ]);
        }
        let label = format!("{} ({} cases)", g.name(), g.points.len());
        curves.push(Curve::new(&label, g.points, mark).colour(k));
    }
    let x = Axis {
        label: if numeric {
            format!("{name} ({})", unit(e, name))
        } else {
            name.into()
        },
        log: false,
        categories: (!numeric).then_some(categories),
    };
    let stem = plot_stem(name);
    plot::chart(
        &report.path(&stem),
        &Chart {
            title: format!("{}: {} against {name}", e.name, e.metric),
            x,
            y: Axis::linear(metric_label),
            curves,
        },
    )?;
    report.figure(&format!("Peak {} against {name}", e.metric), &stem);
    Ok(lines)
}

/// The metric over time for the first finished cases (at most 6).
fn histories(
    report: &mut Report,
    e: &Experiment,
    results: &[CaseResult],
    unit: &str,
) -> Result<()> {
    let mut curves = Vec::new();
    for r in results.iter().filter(|r| r.peak(0).is_some()).take(6) {
        let s = Series::read_csv(&report.path(&format!("cases/case_{:04}.csv", r.id)))?;
        let Some(y) = s.column(&e.metric) else {
            continue;
        };
        let label = r
            .values
            .iter()
            .map(|(k, v)| match v {
                Value::Real(x) => format!("{k}={x:.3}"),
                Value::Text(t) => format!("{k}={t}"),
            })
            .collect::<Vec<_>>()
            .join(", ");
        let label = if label.len() > 40 {
            format!("case {}", r.id)
        } else {
            format!("case {}: {label}", r.id)
        };
        let points = s.rows.iter().map(|row| row[0]).zip(y).collect();
        let colour = curves.len();
        curves.push(Curve::new(&label, points, Mark::Line).colour(colour));
    }
    if curves.is_empty() {
        return Ok(());
    }
    plot::chart(
        &report.path("histories"),
        &Chart {
            title: format!("{}: {} over time", e.name, e.metric),
            x: Axis::linear("time (s)"),
            y: Axis::linear(&format!("{} ({unit})", e.metric)),
            curves,
        },
    )?;
    report.figure(&format!("{} over time, first cases", e.metric), "histories");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::correlation;

    #[test]
    fn correlation_of_lines_is_plus_or_minus_one() {
        let up: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, 2.0 * i as f64 + 1.0)).collect();
        let down: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, -3.0 * i as f64)).collect();
        assert!((correlation(&up) - 1.0).abs() < 1e-12);
        assert!((correlation(&down) + 1.0).abs() < 1e-12);
    }
}
