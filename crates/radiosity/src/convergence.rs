//! Residual histories: a CSV file (`solver,iteration,residual`) and a PNG chart that
//! compares solvers on a log scale (plotters).

use crate::error::{RadiosityError, Result};
use plotters::prelude::*;
use std::path::Path;

/// One solver's history.
pub struct History<'a> {
    pub name: &'a str,
    pub residuals: &'a [f64],
}

pub fn csv(histories: &[History]) -> String {
    let mut s = String::from("solver,iteration,residual\n");
    for h in histories {
        for (i, r) in h.residuals.iter().enumerate() {
            s.push_str(&format!("{},{},{:e}\n", h.name, i + 1, r));
        }
    }
    s
}

pub fn write_csv(path: &Path, histories: &[History]) -> Result<()> {
    irradia_core::io::write_atomic(path, csv(histories).as_bytes())
        .map_err(|e| RadiosityError::Failure(format!("cannot write {}: {e}", path.display())))
}

/// Draws residual against iteration (log y) for each history into a PNG.
pub fn write_chart(path: &Path, histories: &[History], title: &str) -> Result<()> {
    let fail = |e: String| RadiosityError::Failure(format!("cannot draw {}: {e}", path.display()));
    let tmp = path.with_extension("tmp.png");
    {
        let root = BitMapBackend::new(&tmp, (900, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
        let xmax = histories
            .iter()
            .map(|h| h.residuals.len())
            .max()
            .unwrap_or(1)
            .max(2);
        let pos = |r: f64| r.max(1e-16);
        let ymin = histories
            .iter()
            .flat_map(|h| h.residuals.iter().copied())
            .filter(|r| *r > 0.0 && r.is_finite())
            .fold(1.0f64, f64::min)
            .max(1e-16)
            * 0.5;
        let ymax = histories
            .iter()
            .flat_map(|h| h.residuals.iter().copied())
            .filter(|r| r.is_finite())
            .fold(1e-12f64, f64::max)
            * 2.0;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d((1usize..xmax).log_scale(), (ymin..ymax).log_scale())
            .map_err(|e| fail(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("iteration (sweep, term, shot or gather)")
            .y_desc("relative residual")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| fail(e.to_string()))?;
        let colours = [
            RED,
            BLUE,
            GREEN,
            MAGENTA,
            CYAN,
            BLACK,
            RGBColor(200, 120, 0),
        ];
        for (k, h) in histories.iter().enumerate() {
            let c = colours[k % colours.len()];
            chart
                .draw_series(LineSeries::new(
                    h.residuals
                        .iter()
                        .enumerate()
                        .map(|(i, r)| (i + 1, pos(*r))),
                    c.stroke_width(2),
                ))
                .map_err(|e| fail(e.to_string()))?
                .label(h.name)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| fail(e.to_string()))?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| fail(e.to_string()))
}
