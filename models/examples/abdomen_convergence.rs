//! The abdomen's static outputs under the default press on four meshes 4× apart in triangles
//! (h halved) with Richardson extrapolation of the last three (`verify::richardson`):
//! observed order, extrapolated value and estimated error. `nested` splits the base mesh
//! into four 0–3 times; `remesh` meshes base × 4^k target triangles afresh (with the
//! grading, the spacing at the part ends shrinks as the grading asks).
//!
//! cargo run --release -p models --example abdomen_convergence -- [element] [formulation] [nu] [base triangles] [mesh_grading] [nested|remesh]
//!
//! defaults: tri6 displacement 0.45 750 0 nested

use models::scene::abdomen::Abdomen;
use models::scene::Scene;
use models::verify::richardson::extrapolate;

const OUTPUTS: [(usize, &str); 6] = [
    (0, "floor_stress_mean"),
    (1, "floor_stress_max"),
    (2, "floor_triangles_vm_mean"),
    (4, "cavity_vm_mean"),
    (7, "apex_uy"),
    (9, "floor_mid_uy"),
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or(default.into());
    let (element, formulation) = (arg(0, "tri6"), arg(1, "displacement"));
    let (nu, base): (f64, f64) = (arg(2, "0.45").parse()?, arg(3, "750").parse()?);
    let grading: f64 = arg(4, "0").parse()?;
    let remesh = arg(5, "nested") == "remesh";
    let mut rows = Vec::new();
    for subdivisions in 0..4 {
        let mut s = Abdomen::new();
        s.set_str("element", &element)?;
        s.set_str("formulation", &formulation)?;
        s.set("cavity_nu", nu)?;
        s.set("mesh_grading", grading)?;
        if remesh {
            s.set("target_triangles", base * 4f64.powi(subdivisions))?;
        } else {
            s.set("target_triangles", base)?;
            s.set("mesh_subdivisions", f64::from(subdivisions))?;
        }
        s.initialize(0.0)?;
        let u = s.static_displacement(0.8)?;
        let out = s.evaluate(&u, 0.8)?;
        let triangles = s.meshed().map_or(0, |m| m.mesh.triangles().len());
        println!(
            "subdivisions {subdivisions}: {triangles} triangles, {} dofs",
            u.len()
        );
        rows.push(out);
    }
    println!("output: values coarse to fine | order, extrapolated, estimated error of the finest");
    for (k, name) in OUTPUTS {
        let values: Vec<f64> = rows.iter().map(|r| r[k]).collect();
        let fit = extrapolate([values[1], values[2], values[3]], 2.0);
        let fit = match fit {
            Ok(e) => format!(
                "{:.2}, {:.6e}, {:.1e} ({:.2} %)",
                e.order,
                e.value,
                e.error,
                100.0 * e.error / e.value.abs()
            ),
            Err(e) => format!("none: {e}"),
        };
        let values: Vec<String> = values.iter().map(|v| format!("{v:.6e}")).collect();
        println!("{name}: {} | {fit}", values.join(", "));
    }
    Ok(())
}
