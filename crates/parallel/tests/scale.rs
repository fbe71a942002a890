//! The closed-form compositing prediction of `scale` against the alpha-beta model
//! applied to the messages a real composite sent: the same link time, so the formula
//! describes the algorithm that runs.

mod common;

use common::*;
use irradia_parallel::comm::{run_local, Comm, LocalOptions, MessageRecord};
use irradia_parallel::composite::{self, CompositeOptions, Layer, Strategy};
use irradia_parallel::netmodel::NetModel;
use irradia_parallel::scale::{composite_time, CompositeCase};

/// Every rank's sent messages of one dense depth composite.
fn recorded(ranks: usize, strategy: Strategy) -> Vec<MessageRecord> {
    let rects = random_rects(30, 5, 255);
    let opts = CompositeOptions {
        rle: false,
        ..Default::default()
    };
    run_local(ranks, LocalOptions::default(), |c| {
        let layer: Layer<[u8; 4]> = render_opaque(&block(&rects, c.rank(), ranks));
        composite::composite(c, strategy, layer, &opts).unwrap();
        c.log().records()
    })
    .into_iter()
    .flat_map(|r| r.unwrap())
    .collect()
}

#[test]
fn predicted_composite_time_matches_the_recorded_messages() {
    // Latency and bandwidth both large enough that a wrong message count or size shows.
    let model = NetModel {
        alpha: 1e-3,
        beta: 1e6,
    };
    let pixels = (W * H) as u64;
    for (ranks, strategy, k) in [
        (2, Strategy::BinarySwap, 2),
        (4, Strategy::BinarySwap, 2),
        (8, Strategy::BinarySwap, 2),
        (4, Strategy::DirectSend, 4),
        (8, Strategy::RadixK(4), 4),
    ] {
        let msgs = recorded(ranks, strategy);
        let measured =
            model.stage_time(&msgs, "composite", ranks) + model.stage_time(&msgs, "gather", ranks);
        // RGBA8 + f32 depth = 8 bytes a pixel.
        let case = CompositeCase {
            pixels,
            bytes_per_pixel: 8,
            bricks: false,
            gather: true,
        };
        let predicted = composite_time(model, ranks, k, case, 0.0).network_s;
        let rel = (measured / predicted - 1.0).abs();
        eprintln!(
            "{ranks} ranks {}: recorded {measured:.4} s, predicted {predicted:.4} s",
            strategy.name()
        );
        assert!(
            rel < 1e-9,
            "{ranks} ranks {}: recorded {measured} s, predicted {predicted} s",
            strategy.name()
        );
    }
}
