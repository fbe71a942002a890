//! `[[labels]]`: captions drawn over the rendered image ([`crate::Label`]).

use super::reader::{Result, Val};
use crate::label::Label;
use irradia_core::Rgb;

/// Reads the optional `labels` array: `text`, `at = [x, y]` (the centre, fractions of
/// the image from the top left), `height` (fraction of the image height, default 0.05)
/// and `color` (default white).
pub fn read_labels(v: Option<Val>) -> Result<Vec<Label>> {
    let Some(v) = v else {
        return Ok(Vec::new());
    };
    let mut labels = Vec::new();
    for item in v.array()? {
        let t = item.table()?;
        let text = t.req("text")?.str()?.to_string();
        let at_v = t.req("at")?;
        let at = at_v.numbers(2)?;
        if at.iter().any(|a| !(0.0..=1.0).contains(a)) {
            return Err(at_v.err("at must lie in [0, 1] x [0, 1] (fractions of the image)"));
        }
        let height = match t.get("height") {
            Some(h) => {
                let x = h.positive()?;
                if x > 1.0 {
                    return Err(h.err("height is a fraction of the image height, at most 1"));
                }
                x
            }
            None => 0.05,
        };
        let color = t.rgb_or("color", Rgb::WHITE)?;
        t.finish()?;
        labels.push(Label {
            text,
            at: [at[0], at[1]],
            height,
            color,
        });
    }
    Ok(labels)
}
