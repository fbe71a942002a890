//! WireGL/Chromium-style parallel submission equals the serial render, and lazy state
//! tracking sends fewer state bytes than broadcasting every change.

use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::sort_common;
use irradia_parallel::submission::{self, Batch};
use irradia_parallel::workload::Workload;

#[test]
fn parallel_submission_equals_serial_and_tracks_state() {
    let w = Workload::Teapot { level: 3 };
    let tris = w.triangles();
    let p = w.pipeline(64, 48);
    // Batches of 16 triangles, cycling through 3 colours.
    let batches: Vec<Batch> = tris
        .chunks(16)
        .enumerate()
        .map(|(i, c)| Batch {
            color: [
                [0.9, 0.3, 0.2, 1.0],
                [0.2, 0.8, 0.3, 1.0],
                [0.3, 0.4, 0.9, 1.0],
            ][i % 3],
            material: 0,
            triangles: c.to_vec(),
        })
        .collect();
    let serial = sort_common::serial(&p, &submission::flatten(&batches));
    for ranks in [1, 2, 3, 4, 6] {
        let out = run_local(ranks, LocalOptions::default(), |c| {
            submission::render(c, &p, &batches, 0).unwrap()
        });
        let mut state = 0;
        let mut broadcast = 0;
        let mut image = None;
        for r in out {
            let (img, st) = r.unwrap();
            state += st.state_bytes;
            broadcast += st.broadcast_state_bytes;
            if img.is_some() {
                image = img;
            }
        }
        assert!(
            image.unwrap() == serial,
            "{ranks} ranks differ from the serial render"
        );
        if ranks > 1 {
            assert!(
                state < broadcast,
                "lazy state {state} bytes vs broadcast {broadcast}"
            );
        }
    }
}
