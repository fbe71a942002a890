//! Per-rank statistics packed for the report: the "balance" section (estimated work
//! per rank of the screen regions used against one strip per rank, and the rays each
//! rank traced) and the "forwarding" section of ray forwarding (per generation, the
//! pixels traced and finished, rays, queries and bytes summed over the ranks). The
//! ranks' numbers travel to rank 0 as little-endian `u64` words.

use crate::comm::{Comm, CommError};
use crate::raytrace_first::{self, RankResult};
use crate::raytrace_forward::ForwardResult;
use crate::sort_first::{imbalance, TileLayout, Tiling};
use irradia_scene::Scene;

/// Little-endian `u64` words of a gathered message (a short tail is dropped).
fn words(b: &[u8]) -> Vec<u64> {
    b.chunks_exact(8)
        .map(|w| u64::from_le_bytes(w.try_into().expect("8 bytes")))
        .collect()
}

/// The "balance" section of the sort-first ray tracer (root only; the others get
/// `None`): estimated costs from the objects' screen bounds and the rays each rank
/// traced, gathered from every rank.
pub fn raytrace_balance<C: Comm>(
    c: &C,
    scene: &Scene,
    tiling: Tiling,
    r: &RankResult,
) -> Result<Option<serde_json::Value>, CommError> {
    let n = c.size();
    let rays = c.gather(0, &r.rays.to_le_bytes())?;
    if r.image.is_none() {
        return Ok(None);
    }
    let layout = raytrace_first::layout(scene, n, tiling);
    let costs = raytrace_first::object_costs(scene, &layout.tiles);
    let (w, h) = (scene.settings.width, scene.settings.height);
    let strips = TileLayout::strips(w, h, n);
    let strip_costs = raytrace_first::object_costs(scene, &strips.tiles);
    let rays: Vec<f64> = rays
        .iter()
        .map(|b| words(b).first().copied().unwrap_or(0) as f64)
        .collect();
    Ok(Some(balance_json(
        tiling,
        &layout,
        &costs,
        &strips,
        &strip_costs,
        Some(&rays),
    )))
}

/// The "forwarding" section of the report (root only): per generation, the pixels
/// traced and finished, the queries asked by all ranks, and the bytes and rays summed
/// over the ranks; and the ranks' cache sizes.
pub fn forward_json<C: Comm>(
    c: &C,
    r: &ForwardResult,
) -> Result<Option<serde_json::Value>, CommError> {
    let mine: Vec<u8> = r
        .generations
        .iter()
        .flat_map(|g| [g.traced, g.finished, g.rays, g.traffic.bytes_sent])
        .chain([r.peak_log_entries as u64])
        .flat_map(u64::to_le_bytes)
        .collect();
    let all = c.gather(0, &mine)?;
    if all.is_empty() {
        return Ok(None);
    }
    let ranks: Vec<Vec<u64>> = all.iter().map(|b| words(b)).collect();
    let generations: Vec<serde_json::Value> = r
        .generations
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let sum = |k: usize| {
                ranks
                    .iter()
                    .map(|w| w.get(4 * i + k).copied().unwrap_or(0))
                    .sum::<u64>()
            };
            serde_json::json!({
                "pixels_traced": sum(0),
                "pixels_finished": sum(1),
                "rays": sum(2),
                "queries": g.traffic.queries_total,
                "bytes": sum(3),
            })
        })
        .collect();
    Ok(Some(serde_json::json!({
        "forwarding": {
            "generations": generations.len(),
            "exchanges": r.exchanges(),
            "per_generation": generations,
            "peak_log_entries_per_rank": ranks.iter().map(|w| w.last().copied().unwrap_or(0)).collect::<Vec<_>>(),
        }
    })))
}

/// The "balance" section of the report: estimated work per rank for the regions used
/// and for one strip per rank, and (ray tracer) the rays each rank traced.
pub fn balance_json(
    tiling: Tiling,
    layout: &TileLayout,
    costs: &[f64],
    strips: &TileLayout,
    strip_costs: &[f64],
    rays: Option<&[f64]>,
) -> serde_json::Value {
    let n = strips.tiles.len();
    let per_rank = layout.rank_costs(costs, n);
    let strip_per_rank = strips.rank_costs(strip_costs, n);
    let mut v = serde_json::json!({
        "regions": if tiling.is_strips() { "strips" } else { "tiles" },
        "tiles": layout.tiles.len(),
        "tiles_per_rank": tiling.per_rank,
        "assign": if tiling.is_strips() { "strips" } else { tiling.assign.name() },
        "estimated_cost_per_rank": per_rank,
        "estimated_imbalance": imbalance(&per_rank),
        "strips_estimated_cost_per_rank": strip_per_rank,
        "strips_estimated_imbalance": imbalance(&strip_per_rank),
        "tile_rects": layout.tiles.iter().map(|t| [t.x0, t.y0, t.x1, t.y1]).collect::<Vec<_>>(),
        "tile_owner": layout.owner,
    });
    if let Some(r) = rays {
        v["rays_per_rank"] = serde_json::json!(r);
        v["rays_imbalance"] = serde_json::json!(imbalance(r));
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sort_first::Assign;

    #[test]
    fn words_read_little_endian_and_drop_a_short_tail() {
        let mut b = 7u64.to_le_bytes().to_vec();
        b.extend(300u64.to_le_bytes());
        b.push(1);
        assert_eq!(words(&b), vec![7, 300]);
    }

    #[test]
    fn balance_of_strips_compares_equal_regions() {
        let strips = TileLayout::strips(8, 8, 2);
        let tiling = Tiling {
            per_rank: 1,
            assign: Assign::Cost,
        };
        let v = balance_json(tiling, &strips, &[1.0, 3.0], &strips, &[1.0, 3.0], None);
        assert_eq!(v["regions"], "strips");
        assert_eq!(v["estimated_cost_per_rank"], serde_json::json!([1.0, 3.0]));
        assert_eq!(v["estimated_imbalance"], v["strips_estimated_imbalance"]);
        assert!(v.get("rays_per_rank").is_none());
    }
}
