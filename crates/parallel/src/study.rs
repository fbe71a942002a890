//! The lecture's cluster study ("Performance on a PC cluster": six nodes, gigabit
//! ethernet; sort-first against sort-last as the triangle count grows, for random
//! triangles, the teapot and marching cubes), re-enacted on one machine: each point runs
//! the real algorithms on [`LocalComm`] ranks, measures the computation stages, and
//! predicts the communication stages from the recorded messages with the alpha-beta
//! [`NetModel`]. Written as CSV and as a PNG chart like the lecture's plots.

use crate::comm::{run_local, CommError, LocalOptions};
use crate::composite::Strategy;
use crate::job::{self, Mode};
use crate::netmodel::NetModel;
use crate::report::Report;
use crate::workload::Workload;
use plotters::prelude::*;
use std::path::Path;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StudyRow {
    pub workload: String,
    pub triangles: usize,
    pub mode: String,
    pub ranks: usize,
    /// Slowest rank's computation (sort, geometry, render), measured.
    pub compute_s: f64,
    /// Communication predicted by the network model.
    pub network_s: f64,
    pub total_s: f64,
    pub bytes: u64,
}

/// Runs one point of the study.
pub fn run_point(
    w: &Workload,
    mode: Mode,
    ranks: usize,
    width: u32,
    height: u32,
    strategy: Strategy,
    model: NetModel,
) -> Result<StudyRow, CommError> {
    let tris = w.triangles();
    let p = w.pipeline(width, height);
    let out = run_local(
        ranks,
        LocalOptions::default(),
        |c| -> Result<Option<Report>, CommError> {
            job::run(c, mode, &p, &tris, strategy)?;
            Report::gather(c)
        },
    );
    let report = out
        .into_iter()
        .next()
        .unwrap()??
        .expect("rank 0 gathers the report");
    let net = Mode::network_stages();
    let compute_s: f64 = report
        .stages
        .iter()
        .filter(|s| !net.contains(&s.name.as_str()))
        .map(|s| s.max_seconds)
        .sum();
    let network_s: f64 = net
        .iter()
        .map(|s| model.stage_time(&report.messages, s, ranks))
        .sum();
    let bytes = report.messages.iter().map(|m| m.bytes as u64).sum();
    Ok(StudyRow {
        workload: w.name().into(),
        triangles: tris.len(),
        mode: mode.name().into(),
        ranks,
        compute_s,
        network_s,
        total_s: compute_s + network_s,
        bytes,
    })
}

pub fn csv(rows: &[StudyRow]) -> String {
    let mut s = String::from("workload,triangles,mode,ranks,compute_s,network_s,total_s,bytes\n");
    for r in rows {
        s += &format!(
            "{},{},{},{},{:.6},{:.6},{:.6},{}\n",
            r.workload, r.triangles, r.mode, r.ranks, r.compute_s, r.network_s, r.total_s, r.bytes
        );
    }
    s
}

/// One panel per workload: frame time against triangles (log-log), one line per mode.
pub fn chart(rows: &[StudyRow], path: &Path) -> Result<(), String> {
    let mut workloads: Vec<&str> = Vec::new();
    for r in rows {
        if !workloads.contains(&r.workload.as_str()) {
            workloads.push(&r.workload);
        }
    }
    let panels = workloads.len().max(1) as u32;
    let root = BitMapBackend::new(path, (520 * panels, 440)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((1, panels as usize));
    for (area, w) in areas.iter().zip(&workloads) {
        let pts: Vec<&StudyRow> = rows.iter().filter(|r| r.workload == *w).collect();
        let xmax = pts.iter().map(|r| r.triangles).max().unwrap_or(10) as f64 * 1.3;
        let xmin = pts.iter().map(|r| r.triangles).min().unwrap_or(1) as f64 / 1.3;
        let ymax = pts.iter().map(|r| r.total_s).fold(1e-4, f64::max) * 1.5;
        let ymin = pts
            .iter()
            .map(|r| r.total_s)
            .fold(f64::INFINITY, f64::min)
            .max(1e-5)
            / 1.5;
        let mut ch = ChartBuilder::on(area)
            .caption(
                format!(
                    "{w}: {} ranks, modelled network",
                    pts.first().map_or(0, |r| r.ranks)
                ),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((xmin..xmax).log_scale(), (ymin..ymax).log_scale())
            .map_err(|e| e.to_string())?;
        ch.configure_mesh()
            .x_labels(6)
            .y_labels(6)
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| format!("{y:.3}"))
            .x_desc("triangles")
            .y_desc("frame time (s)")
            .draw()
            .map_err(|e| e.to_string())?;
        for (mode, color) in [
            ("sort-first", RED),
            ("sort-middle", GREEN),
            ("sort-last", BLUE),
        ] {
            let mut line: Vec<(f64, f64)> = pts
                .iter()
                .filter(|r| r.mode == mode)
                .map(|r| (r.triangles as f64, r.total_s))
                .collect();
            if line.is_empty() {
                continue;
            }
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            ch.draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(mode)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            ch.draw_series(line.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(|e| e.to_string())?;
        }
        ch.configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}
