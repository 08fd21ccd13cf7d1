//! Runs a scene in process the way an FMI importer would, for comparing FMU results:
//!
//! `reference <abdomen|cutblock> <stop_time> <step> [name=value …] [input=<csv>] out=<a,b,…>`
//!
//! `name=value` sets a parameter before initialization (numbers as reals, anything else as a
//! string); the input CSV (`time,<input>,…`) gives input values applied at the
//! communication points listed in it (rows must fall on them, as fmpy's linear interpolation
//! then reproduces the values exactly). Prints `time,<outputs>` after initialization and after
//! every step, with full precision (`{:?}`), to standard output.

use std::process::ExitCode;

use fmu::model::MODELS;

fn run(args: &[String]) -> Result<(), String> {
    let [model, stop, step, rest @ ..] = args else {
        return Err(
            "usage: reference <model> <stop_time> <step> [name=value …] [input=<csv>] out=<a,b,…>"
                .into(),
        );
    };
    let model = MODELS
        .iter()
        .find(|m| m.identifier == model)
        .ok_or(format!("unknown model `{model}`"))?;
    let stop: f64 = stop.parse().map_err(|e| format!("stop_time: {e}"))?;
    let step: f64 = step.parse().map_err(|e| format!("step: {e}"))?;
    let mut scene = (model.create)();
    let mut inputs: Vec<(f64, Vec<(u32, f64)>)> = Vec::new();
    let mut outputs = Vec::new();
    for arg in rest {
        let (key, value) = arg
            .split_once('=')
            .ok_or(format!("argument `{arg}` is not name=value"))?;
        match key {
            "out" => {
                for name in value.split(',') {
                    outputs.push(scene.lookup(name).map_err(|e| e.to_string())?);
                }
            }
            "input" => {
                let text = std::fs::read_to_string(value).map_err(|e| format!("{value}: {e}"))?;
                let mut lines = text.lines();
                let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
                let vrs = header[1..]
                    .iter()
                    .map(|n| scene.lookup(n))
                    .collect::<Result<Vec<_>, _>>()
                    .map_err(|e| e.to_string())?;
                for line in lines {
                    let v: Vec<f64> = line
                        .split(',')
                        .map(|x| x.parse().map_err(|e| format!("{line}: {e}")))
                        .collect::<Result<_, _>>()?;
                    inputs.push((
                        v[0],
                        vrs.iter().copied().zip(v[1..].iter().copied()).collect(),
                    ));
                }
            }
            name => {
                let vr = scene.lookup(name).map_err(|e| e.to_string())?;
                match value.parse::<f64>() {
                    Ok(x) => scene.set_real(vr, &[x]),
                    Err(_) => scene.set_string(vr, value),
                }
                .map_err(|e| e.to_string())?;
            }
        }
    }
    let apply = |scene: &mut Box<dyn models::scene::Scene>, t: f64| -> Result<(), String> {
        if let Some((_, values)) = inputs.iter().rev().find(|(time, _)| *time <= t + 1e-12) {
            for &(vr, x) in values {
                scene.set_real(vr, &[x]).map_err(|e| e.to_string())?;
            }
        }
        Ok(())
    };
    apply(&mut scene, 0.0)?;
    scene.initialize().map_err(|e| e.to_string())?;
    let print = |scene: &mut Box<dyn models::scene::Scene>, t: f64| -> Result<(), String> {
        let mut row = format!("{t:?}");
        for &vr in &outputs {
            let mut x = [0.0];
            scene.get_real(vr, &mut x).map_err(|e| e.to_string())?;
            row += &format!(",{:?}", x[0]);
        }
        println!("{row}");
        Ok(())
    };
    print(&mut scene, 0.0)?;
    let n = (stop / step).round() as usize;
    for k in 0..n {
        let t = k as f64 * step;
        apply(&mut scene, t)?;
        scene.do_step(t, step).map_err(|e| e.to_string())?;
        print(&mut scene, t + step)?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("reference: {e}");
            ExitCode::FAILURE
        }
    }
}
