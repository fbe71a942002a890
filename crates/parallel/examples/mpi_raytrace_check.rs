//! The parallel ray tracer over MPI: run under `mpirun -np N` (scripts/test-mpi.sh runs
//! N = 2 and 3). Every process loads the built-in Whitted scene at 64x48; rank 0
//! compares the image-parallel Whitted image (strips, interleaved tiles, cost-dealt
//! tiles) with the serial render, the object-parallel ray cast (binary swap, radix-k)
//! with the serial ray cast, and the object-parallel Whitted tracer with ray forwarding
//! (`raytrace_forward`, on the Whitted scene and the default scene with its area light
//! and CSG) with the serial render, bit for bit. Prints one line per case and a closing
//! `N passed, N failed`; exits 1 on any failure.

use irradia_parallel::comm::{Comm, MpiComm};
use irradia_parallel::composite::Strategy;
use irradia_parallel::sort_first::{Assign, Tiling};
use irradia_parallel::{raytrace_first, raytrace_forward, raytrace_last};
use irradia_render::{driver, Whitted};
use std::time::Duration;

fn main() {
    let comm = MpiComm::init(Duration::from_secs(20)).expect("MPI initialises once");
    let (rank, p) = (comm.rank(), comm.size());
    let mut scene = irradia_scene::builtin::load("whitted").expect("built-in scene");
    scene.settings.width = 64;
    scene.settings.height = 48;
    let (mut passed, mut failed) = (0, 0);
    let mut tally = |ok: bool, what: String| {
        if rank == 0 {
            println!("{} {what} np={p}", if ok { "ok  " } else { "FAIL" });
            if ok {
                passed += 1
            } else {
                failed += 1
            }
        }
    };
    let serial = driver::render_with(&Whitted::new(&scene), &scene, &Default::default())
        .expect("serial render")
        .image;
    for tiling in [
        Tiling::STRIPS,
        Tiling {
            per_rank: 3,
            assign: Assign::Interleaved,
        },
        Tiling {
            per_rank: 4,
            assign: Assign::Cost,
        },
    ] {
        let r = raytrace_first::render(&comm, &scene, tiling, 0).unwrap_or_else(|e| comm.fail(&e));
        if rank == 0 {
            let img = raytrace_first::to_image(&r.image.expect("rank 0 holds the image"));
            tally(
                img.pixels() == serial.pixels(),
                format!("sort-first ray tracing {tiling:?}"),
            );
        }
    }
    let cast = raytrace_last::serial(&scene);
    for s in [Strategy::BinarySwap, Strategy::RadixK(3)] {
        let got = raytrace_last::render(&comm, &scene, s, 0).unwrap_or_else(|e| comm.fail(&e));
        if rank == 0 {
            tally(
                got.as_ref() == Some(&cast),
                format!("sort-last ray casting {}", s.name()),
            );
        }
    }
    for name in ["whitted", "default"] {
        let mut scene = irradia_scene::builtin::load(name).expect("built-in scene");
        scene.settings.width = 64;
        scene.settings.height = 48;
        let serial = driver::render_with(&Whitted::new(&scene), &scene, &Default::default())
            .expect("serial render")
            .image;
        for tiling in [
            Tiling::STRIPS,
            Tiling {
                per_rank: 3,
                assign: Assign::Interleaved,
            },
        ] {
            let r = raytrace_forward::render(&comm, &scene, tiling, 0)
                .unwrap_or_else(|e| comm.fail(&e));
            if rank == 0 {
                let img = raytrace_first::to_image(&r.image.expect("rank 0 holds the image"));
                tally(
                    img.pixels() == serial.pixels(),
                    format!(
                        "sort-last Whitted ray tracing with ray forwarding, {name}, {tiling:?} ({} generations)",
                        r.generations.len()
                    ),
                );
            }
        }
    }
    if rank == 0 {
        println!("{passed} passed, {failed} failed");
        if failed > 0 {
            std::process::exit(1);
        }
    }
}
