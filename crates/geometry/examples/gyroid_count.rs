//! Prints the size of the benchmark gyroid mesh and checks it is closed inside the grid.
use irradia_geometry::generators::{gyroid::BENCHMARK_GRID, gyroid_mesh};
use std::collections::HashMap;
fn main() {
    let n: u32 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(BENCHMARK_GRID);
    let t = std::time::Instant::now();
    let m = gyroid_mesh(n);
    println!(
        "grid {n}^3: {} vertices, {} triangles in {:.2?}",
        m.positions.len(),
        m.indices.len(),
        t.elapsed()
    );
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for t in &m.indices {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let open = edges.values().filter(|&&c| c != 2).count();
    println!("edges used other than twice (boundary of the grid): {open}");
}
