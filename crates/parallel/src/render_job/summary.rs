//! The report of one frame: the text summary (per stage the slowest rank's time, the
//! bytes sent and the load imbalance; the balance of the screen regions or the ray
//! forwarding generations) and the JSON file (the per-rank, per-stage [`Report`] with
//! its "balance" or "forwarding" section).

use super::RenderJob;
use crate::report::Report;

/// The summary printed after a frame, one line each.
pub fn summary_lines(
    job: &RenderJob,
    report: &Report,
    balance: Option<&serde_json::Value>,
) -> Vec<String> {
    let (width, height) = job.size();
    let mut lines = vec![format!(
        "{} ({:?}) of {} ({}) on {} ranks, {width}x{height}{}:",
        job.mode.name(),
        job.renderer,
        job.input.name(),
        job.input.describe(),
        report.ranks,
        match &job.display {
            Some((l, c)) => format!(" onto {} display tiles ({c} columns)", l.tiles.len()),
            None => String::new(),
        }
    )];
    for s in &report.stages {
        lines.push(format!(
            "  {:<13} {:>9.3} ms  {:>12} bytes sent  imbalance {:.2}",
            s.name,
            s.max_seconds * 1e3,
            s.total_bytes_sent,
            s.load_imbalance
        ));
    }
    if let Some(f) = balance.and_then(|b| b.get("forwarding")) {
        lines.push(format!(
            "  ray forwarding: {} generations, {} exchanges of queries",
            f["generations"], f["exchanges"]
        ));
        for (i, g) in f["per_generation"]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
        {
            lines.push(format!(
                "    generation {}: {} pixels traced, {} finished, {} rays, {} queries, {} bytes sent",
                i + 1,
                g["pixels_traced"],
                g["pixels_finished"],
                g["rays"],
                g["queries"],
                g["bytes"]
            ));
        }
    } else if let Some(b) = balance {
        lines.push(format!(
            "  regions: {} ({} tiles); estimated work imbalance {:.3} (strips {:.3}){}",
            b["regions"].as_str().unwrap_or(""),
            b["tiles"],
            b["estimated_imbalance"].as_f64().unwrap_or(0.0),
            b["strips_estimated_imbalance"].as_f64().unwrap_or(0.0),
            match b.get("rays_imbalance").and_then(|v| v.as_f64()) {
                Some(x) => format!("; rays traced imbalance {x:.3}"),
                None => String::new(),
            }
        ));
    }
    lines
}

/// The report as pretty JSON, with the "balance" section (or the "forwarding" one)
/// added to the top level.
pub fn report_json(report: &Report, balance: Option<&serde_json::Value>) -> String {
    let mut json: serde_json::Value =
        serde_json::from_str(&report.to_json()).expect("Report::to_json writes valid JSON");
    if let (Some(obj), Some(b)) = (json.as_object_mut(), balance) {
        obj.insert("balance".into(), b.clone());
    }
    serde_json::to_string_pretty(&json).expect("a JSON value serialises")
}
