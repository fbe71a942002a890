//! Sort-first, sort-middle and sort-last over `LocalComm` equal the serial render of the
//! same triangles bit for bit, for the three workloads and several rank counts.

use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::composite::{CompositeOptions, Operator, Strategy};
use irradia_parallel::workload::Workload;
use irradia_parallel::{frame, sort_first, sort_last, sort_middle};

const W: u32 = 64;
const H: u32 = 48;

fn workloads() -> Vec<Workload> {
    vec![
        Workload::RandomTriangles {
            count: 600,
            seed: 3,
        },
        Workload::Teapot { level: 3 },
        Workload::MarchingCubes { n: 10 },
    ]
}

#[test]
fn every_sorting_scheme_equals_the_serial_render() {
    for w in workloads() {
        let tris = w.triangles();
        let p = w.pipeline(W, H);
        let serial = frame::serial(&p, &tris);
        let covered = serial.active_fraction(Operator::Depth);
        assert!(
            covered > 0.05,
            "{}: only {covered} of the screen covered",
            w.name()
        );
        for ranks in [1, 2, 3, 5, 8] {
            for mode in ["sort-first", "sort-middle", "sort-last"] {
                let out = run_local(ranks, LocalOptions::default(), |c| match mode {
                    "sort-first" => sort_first::render(c, &p, &tris, 0).unwrap(),
                    "sort-middle" => sort_middle::render(c, &p, &tris, 0).unwrap(),
                    _ => sort_last::render(
                        c,
                        &p,
                        &tris,
                        Strategy::BinarySwap,
                        &CompositeOptions::default(),
                    )
                    .unwrap(),
                });
                let img = out.into_iter().next().unwrap().unwrap().unwrap();
                let diff = img
                    .color
                    .iter()
                    .zip(&serial.color)
                    .filter(|(a, b)| a != b)
                    .count();
                assert!(
                    img == serial,
                    "{} {mode} with {ranks} ranks: {diff} pixels differ",
                    w.name()
                );
            }
        }
    }
}
