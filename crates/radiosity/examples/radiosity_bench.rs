//! Timing of the measured Cornell box with blocks by hierarchical radiosity (and, for
//! small meshes, the matrix methods), phase by phase. Used by bench/radiosity/run.sh.
//!
//! `cargo run --release -p irradia-radiosity --example radiosity_bench -- ELEMENTS [METHOD SOLVER EPS]`
//! (hierarchical: ELEMENTS is the target number of leaves) prints one line: `elements=... total_s=... <phase>_s=... iterations=... cpu_to_solve_end_s=...`.

use irradia_radiosity::formfactor::{Method, Params};
use irradia_radiosity::mesh::MeshOptions;
use irradia_radiosity::pipeline::{run, Config, NoProgress};
use irradia_radiosity::scenes;
use irradia_radiosity::solver::hierarchical::HierarchicalOptions;
use irradia_radiosity::solver::SolverKind;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let elements: f64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(10_000.0);
    let method = args
        .get(2)
        .and_then(|s| Method::parse(s))
        .unwrap_or(Method::Hemicube);
    let solver = args
        .get(3)
        .and_then(|s| SolverKind::parse(s))
        .unwrap_or(SolverKind::Hierarchical);
    let eps: f64 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1e-3);
    let specs = scenes::cornell_measured();
    let mesh = irradia_radiosity::Mesh::build(&specs, MeshOptions::default()).unwrap();
    let area = mesh.total_area() / elements;
    let cfg = Config {
        mesh: MeshOptions {
            max_element_area: Some(area),
            max_elements: 10_000_000,
        },
        method,
        params: Params {
            hemicube_resolution: 64,
            ..Default::default()
        },
        solver,
        hierarchical: HierarchicalOptions {
            bf_epsilon: eps,
            // Hierarchical: the leaf area that gives this many leaves.
            target_leaves: Some(elements as usize),
            ..Default::default()
        },
        ..Default::default()
    };
    let t = Instant::now();
    let r = run(&specs, &cfg, &NoProgress).unwrap();
    let t_solve = t.elapsed().as_secs_f64();
    let cpu_solve = process_cpu_s();
    let t2 = Instant::now();
    let dm = r.display_mesh();
    let t_display = t2.elapsed().as_secs_f64();
    let mut line = format!(
        "threads={} target_elements={} elements={} total_s={:.3} display_mesh_s={:.3} residual={:.2e} iterations={}",
        rayon::current_num_threads(),
        elements,
        r.mesh.len(),
        t_solve,
        t_display,
        r.solution.residual,
        r.solution.history.len()
    );
    for (p, d) in &r.timings {
        line.push_str(&format!(
            " [{}]={:.3}",
            p.replace(' ', "_"),
            d.as_secs_f64()
        ));
    }
    for n in &r.notes {
        line.push_str(&format!(" note=\"{n}\""));
    }
    line.push_str(&format!(" display_vertices={}", dm.positions.len()));
    // CPU seconds of the whole process up to the end of the solve (user + system, all
    // threads; Linux only): on a loaded machine the wall clock says little, this does.
    if let Some(c) = cpu_solve {
        line.push_str(&format!(" cpu_to_solve_end_s={c:.3}"));
    }
    println!("{line}");
}

/// User + system CPU seconds of this process so far, from /proc/self/stat (fields 14
/// and 15, in clock ticks of 1/100 s, the Linux default); `None` elsewhere.
fn process_cpu_s() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is in parentheses and may hold spaces.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}
