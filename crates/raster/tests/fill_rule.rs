//! Watertightness of the rasterizer: a mesh of abutting triangles covers every pixel
//! inside it exactly once (top-left fill rule, fixed-point edge functions).

use irradia_core::Rng;
use irradia_raster::{for_each_fragment, Rect, ScreenTriangle, ScreenVertex};

fn sv(x: f32, y: f32) -> ScreenVertex {
    ScreenVertex {
        x,
        y,
        z: 0.5,
        inv_w: 1.0,
        ..Default::default()
    }
}

fn tri(a: (f32, f32), b: (f32, f32), c: (f32, f32), flip: bool) -> ScreenTriangle {
    let v = if flip {
        [sv(a.0, a.1), sv(c.0, c.1), sv(b.0, b.1)]
    } else {
        [sv(a.0, a.1), sv(b.0, b.1), sv(c.0, c.1)]
    };
    ScreenTriangle {
        v,
        id: 0,
        material: 0,
    }
}

/// Writes per pixel of a `w` x `h` screen.
fn count(tris: &[ScreenTriangle], w: u32, h: u32) -> Vec<u32> {
    let mut n = vec![0u32; (w * h) as usize];
    for t in tris {
        for_each_fragment(t, &Rect::full(w, h), |x, y, _| n[(y * w + x) as usize] += 1);
    }
    n
}

#[test]
fn jittered_grid_of_split_quads_covers_each_pixel_once() {
    let (w, h) = (96u32, 80u32);
    let mut rng = Rng::new(11, 0);
    for trial in 0..20 {
        // Outer boundary at sub-pixel offsets that never hit a pixel centre.
        let (x0, y0, x1, y1) = (5.3f32, 4.7, 90.2, 75.8);
        let (nx, ny) = (13usize, 11usize);
        let mut grid = vec![(0.0f32, 0.0f32); (nx + 1) * (ny + 1)];
        for j in 0..=ny {
            for i in 0..=nx {
                let mut x = x0 + (x1 - x0) * i as f32 / nx as f32;
                let mut y = y0 + (y1 - y0) * j as f32 / ny as f32;
                if i > 0 && i < nx && j > 0 && j < ny {
                    // Interior vertices jitter by up to a third of a cell, at 1/256 or
                    // finer offsets, and some land exactly on pixel centres.
                    x += (rng.next_f32() - 0.5) * 4.0;
                    y += (rng.next_f32() - 0.5) * 4.0;
                    if rng.next_f32() < 0.2 {
                        x = x.floor() + 0.5;
                        y = y.floor() + 0.5;
                    }
                }
                grid[j * (nx + 1) + i] = (x, y);
            }
        }
        let mut tris = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let a = grid[j * (nx + 1) + i];
                let b = grid[j * (nx + 1) + i + 1];
                let c = grid[(j + 1) * (nx + 1) + i + 1];
                let d = grid[(j + 1) * (nx + 1) + i];
                // Alternate the diagonal and the winding.
                if (i + j + trial) % 2 == 0 {
                    tris.push(tri(a, b, c, rng.next_f32() < 0.5));
                    tris.push(tri(a, c, d, rng.next_f32() < 0.5));
                } else {
                    tris.push(tri(a, b, d, rng.next_f32() < 0.5));
                    tris.push(tri(b, c, d, rng.next_f32() < 0.5));
                }
            }
        }
        let n = count(&tris, w, h);
        for y in 0..h {
            for x in 0..w {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                let inside = cx > x0 && cx < x1 && cy > y0 && cy < y1;
                assert_eq!(
                    n[(y * w + x) as usize],
                    inside as u32,
                    "trial {trial}: pixel ({x}, {y})"
                );
            }
        }
    }
}

#[test]
fn fan_around_a_shared_vertex_covers_each_pixel_once() {
    let (w, h) = (80u32, 80u32);
    let mut rng = Rng::new(5, 1);
    for trial in 0..20 {
        let c = (40.0 + rng.next_f32(), 40.0 + rng.next_f32());
        // Every fourth fan has its shared vertex exactly on a pixel centre.
        let centre = if trial % 4 == 0 { (40.5, 40.5) } else { c };
        let k = 40 + trial;
        // A convex ring: a circle at random sorted angles.
        let mut angles: Vec<f32> = (0..k)
            .map(|_| rng.next_f32() * std::f32::consts::TAU)
            .collect();
        angles.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let ring: Vec<(f32, f32)> = angles
            .iter()
            .map(|a| (40.37 + 30.0 * a.cos(), 40.61 + 30.0 * a.sin()))
            .collect();
        let tris: Vec<ScreenTriangle> = (0..k)
            .map(|i| tri(centre, ring[i], ring[(i + 1) % k], i % 3 == 0))
            .collect();
        let n = count(&tris, w, h);
        // Inside the ring polygon (pixel centres within 1e-3 px of its boundary are
        // skipped: float and fixed point may disagree there).
        for y in 0..h {
            for x in 0..w {
                let p = (x as f32 + 0.5, y as f32 + 0.5);
                let mut min_d = f32::INFINITY;
                for i in 0..k {
                    let (a, b) = (ring[i], ring[(i + 1) % k]);
                    let (ex, ey) = (b.0 - a.0, b.1 - a.1);
                    let d = (ex * (p.1 - a.1) - ey * (p.0 - a.0)) / (ex * ex + ey * ey).sqrt();
                    min_d = min_d.min(d);
                }
                if min_d.abs() < 1e-3 {
                    continue;
                }
                let inside = min_d > 0.0;
                assert_eq!(
                    n[(y * w + x) as usize],
                    inside as u32,
                    "trial {trial}: pixel ({x}, {y}) d {min_d}"
                );
            }
        }
    }
}

#[test]
fn shared_edge_through_pixel_centres_is_drawn_once() {
    // A horizontal, a vertical and a diagonal edge passing exactly through centres.
    for (a, b) in [
        ((0.5, 10.5), (40.5, 10.5)),
        ((20.5, 0.5), (20.5, 30.5)),
        ((0.5, 0.5), (30.5, 30.5)),
    ] {
        let t1 = tri(a, b, (0.0, 40.0), false);
        let t2 = tri(b, a, (40.0, 0.0), false);
        let n = count(&[t1, t2], 48, 48);
        assert!(
            n.iter().all(|&c| c <= 1),
            "double write on edge {a:?}-{b:?}"
        );
        // Every centre inside the edge (not at its ends, which border other
        // triangles) is written by exactly one of the two.
        for s in 1..30 {
            let t = s as f32 / 30.0;
            let (x, y) = (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
            if (x - 0.5).fract() == 0.0 && (y - 0.5).fract() == 0.0 && x < 40.0 && y < 40.0 {
                assert_eq!(
                    n[(y as usize) * 48 + x as usize],
                    1,
                    "edge {a:?}-{b:?} at ({x}, {y})"
                );
            }
        }
    }
}

#[test]
fn the_geometry_stage_cull_keeps_exactly_the_triangles_that_cover_a_pixel() {
    use irradia_raster::rasterizer::may_cover;
    use irradia_raster::CullMode;
    let mut rng = Rng::new(9, 2);
    let screen = Rect::full(16, 16);
    let (mut exact, mut culled) = (0, 0);
    for _ in 0..20_000 {
        // Sub-pixel and pixel-sized triangles around pixel centres.
        let c = (4.0 + rng.next_f32() * 8.0, 4.0 + rng.next_f32() * 8.0);
        let s = 0.2 + rng.next_f32() * 1.5;
        let mut p = || {
            (
                c.0 + (rng.next_f32() - 0.5) * s,
                c.1 + (rng.next_f32() - 0.5) * s,
            )
        };
        let t = tri(p(), p(), p(), false);
        let mut n = 0;
        for_each_fragment(&t, &screen, |_, _, _| n += 1);
        if may_cover(&t, CullMode::None, &screen) {
            // Larger boxes are kept without an exact test; boxes of up to
            // EXACT_CULL_CENTRES pixel centres are exact: kept means covered.
            let (x0, x1, y0, y1) = irradia_raster::rasterizer::row_range(&t);
            let centres = (x1.min(15) - x0.max(0) + 1) * (y1.min(15) - y0.max(0) + 1);
            if centres <= irradia_raster::rasterizer::EXACT_CULL_CENTRES {
                assert!(n > 0, "{t:?} was kept but covers no pixel");
                exact += 1;
            }
            continue;
        }
        culled += 1;
        assert_eq!(n, 0, "{t:?} was culled but covers {n} pixels");
    }
    // Both outcomes were exercised.
    assert!(
        exact > 1000 && culled > 1000,
        "{exact} kept exactly, {culled} culled"
    );
}
