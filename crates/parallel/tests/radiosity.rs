//! Hierarchical radiosity on several ranks (`irradia_parallel::radiosity`): on 1 to 5
//! ranks (threads of this process) the radiosities, the leaves, the iteration history
//! and the link count equal the one-process solve bit for bit, also with more ranks
//! than patches; bad options fail on every rank alike; a rank that dies ends the job
//! with an error naming it.

use irradia_parallel::comm::{run_local, Comm, LocalOptions};
use irradia_parallel::radiosity::solve_distributed;
use irradia_radiosity::mesh::MeshOptions;
use irradia_radiosity::scenes;
use irradia_radiosity::solver::hierarchical::{self, HierarchicalOptions, HierarchicalResult};
use irradia_radiosity::{Mesh, RadiosityError};
use std::time::{Duration, Instant};

fn cornell() -> Mesh {
    let specs = scenes::builtin("cornell").expect("the built-in Cornell box");
    Mesh::build(&specs, MeshOptions::default()).unwrap()
}

fn options(leaves: usize) -> HierarchicalOptions {
    HierarchicalOptions {
        target_leaves: Some(leaves),
        bf_epsilon: 1e-3,
        visibility_rays: 4,
        ..Default::default()
    }
}

fn local(seconds: u64) -> LocalOptions {
    LocalOptions {
        timeout: Duration::from_secs(seconds),
        delay: None,
    }
}

fn on_ranks(n: usize, mesh: &Mesh, opts: HierarchicalOptions) -> HierarchicalResult {
    let mut outs = run_local(n, local(60), |c| {
        irradia_render::pool::with_threads(Some(1), || solve_distributed(c, mesh, opts))
            .map_err(|e| RadiosityError::Failure(e.to_string()))
            .and_then(|r| r)
    });
    for (r, o) in outs.iter().enumerate().skip(1) {
        assert!(
            matches!(o, Ok(Ok(None))),
            "rank {r}: {:?}",
            o.as_ref().err()
        );
    }
    match outs.swap_remove(0) {
        Ok(Ok(Some(r))) => r,
        Ok(Ok(None)) => panic!("rank 0 returned no result"),
        Ok(Err(e)) => panic!("rank 0: {e}"),
        Err(e) => panic!("rank 0: {e}"),
    }
}

fn bits(b: &[[f64; 3]]) -> Vec<[u64; 3]> {
    b.iter().map(|x| x.map(f64::to_bits)).collect()
}

fn assert_same(a: &HierarchicalResult, b: &HierarchicalResult, what: &str) {
    assert_eq!(a.solution.b.len(), b.solution.b.len(), "{what}: leaves");
    assert!(
        bits(&a.solution.b) == bits(&b.solution.b),
        "{what}: radiosities differ"
    );
    let hist = |r: &HierarchicalResult| {
        r.solution
            .history
            .iter()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(hist(a), hist(b), "{what}: history");
    assert_eq!(a.links, b.links, "{what}: links");
    assert_eq!(a.nodes, b.nodes, "{what}: nodes");
    for (x, y) in a.mesh.elements.iter().zip(&b.mesh.elements) {
        assert_eq!(x.patch, y.patch, "{what}: leaf patches");
        assert_eq!(x.area.to_bits(), y.area.to_bits(), "{what}: leaf areas");
    }
}

#[test]
fn the_cornell_box_on_any_number_of_ranks_equals_one_process() {
    let mesh = cornell();
    let opts = options(1500);
    let serial = hierarchical::solve(&mesh, opts, None).unwrap();
    assert!(serial.links > 1000, "{} links", serial.links);
    for n in 1..=5 {
        assert_same(&on_ranks(n, &mesh, opts), &serial, &format!("{n} ranks"));
    }
}

#[test]
fn more_ranks_than_patches_still_equals_one_process() {
    // Six patches on seven ranks: a rank owns no patch.
    let specs = scenes::closed_box(1.0, [0.5, 0.4, 0.3], [1.0; 3]);
    let mesh = Mesh::build(&specs, MeshOptions::default()).unwrap();
    let opts = HierarchicalOptions {
        max_element_area: 1.0 / 64.0,
        bf_epsilon: 1e-3,
        visibility_rays: 0,
        rounds: 2,
        ..Default::default()
    };
    let serial = hierarchical::solve(&mesh, opts, None).unwrap();
    assert_same(&on_ranks(7, &mesh, opts), &serial, "7 ranks, 6 patches");
}

#[test]
fn bad_options_fail_on_every_rank_alike() {
    let mesh = cornell();
    let opts = HierarchicalOptions {
        max_element_area: 1e-3,
        max_elements: 1000,
        ..Default::default()
    };
    let outs = run_local(3, local(20), |c| solve_distributed(c, &mesh, opts));
    for (r, o) in outs.iter().enumerate() {
        match o {
            Ok(Err(RadiosityError::Input(m))) => assert!(m.contains("limit"), "rank {r}: {m}"),
            other => panic!("rank {r}: {:?}", other.as_ref().map(|x| x.as_ref().err())),
        }
    }
}

#[test]
fn a_rank_that_dies_ends_the_job_with_an_error_naming_it() {
    let mesh = cornell();
    let opts = options(4000);
    for dying in [1, 2] {
        let t = Instant::now();
        let outs = run_local(3, local(20), |c| {
            if c.rank() == dying {
                panic!("killed");
            }
            solve_distributed(c, &mesh, opts)
        });
        let msg = match &outs[0] {
            Ok(Err(e)) => e.to_string(),
            Err(e) => e.to_string(),
            Ok(Ok(_)) => panic!("rank 0 finished although rank {dying} died"),
        };
        assert!(msg.contains(&format!("rank {dying}")), "{msg}");
        assert!(
            t.elapsed() < Duration::from_secs(15),
            "took {:?}",
            t.elapsed()
        );
    }
}
