//! The drop at rest: the scene's game method (4 substeps of 4 iterations, SIMD, exact
//! joints, contacts warm-started and soft at 90 Hz, joint damping 0.2 N m s/rad and friction
//! 1 N m, deep overlap pushed out at no more than 3 m/s, sleeping on), over layouts: each
//! pile is one sample of a chaotic outcome, and the survey's result is the same on every
//! machine (tests/determinism.rs).

use super::*;

/// Over layouts 1-128 x both spines (256 piles of 10 s, about 100 s on 2 cores; each layout's
/// row: `rodlab layouts scenes/ragdoll_drop.toml --variant game --seeds 1-128`):
/// - every run finishes (no NaN, no explosion);
/// - every pile is at rest after 10 s: every body asleep, or every surface point under the
///   sleep speed (docs/rest.md, The drop at rest);
/// - at rest the overlapping contact points overlap by under 1 mm, on the mean over the piles
///   (0.40 mm), and in each pile under 2 mm (at most 0.63 mm).
#[test]
fn every_drop_pile_comes_to_rest_at_the_game_method() {
    let runs = survey_over("game", &Overrides::default(), 1..=128);
    let ends: Vec<_> = (runs.iter())
        .map(|r| match &r.end {
            Ok(end) => end,
            Err(why) => panic!("seed {} {}: {why}", r.seed, r.spine),
        })
        .collect();
    let restless: Vec<String> = (runs.iter().zip(&ends))
        .filter(|(_, e)| e.still_moving > 0)
        .map(|(r, e)| format!("{} {} {:?}", r.seed, r.spine, e.fastest))
        .collect();
    let overlap: Vec<f32> = ends.iter().map(|e| e.overlap_at_rest_mm).collect();
    let asleep: Vec<f32> = (ends.iter())
        .filter_map(|e| e.all_asleep_from.map(|f| f as f32))
        .collect();
    println!(
        "at rest after 10 s: {} of {}; not: {restless:?}; all asleep from frame {:.0} on average \
         ({} piles); overlap at rest {:.2} mm on average, at most {:.2} mm",
        ends.len() - restless.len(),
        ends.len(),
        mean(&asleep),
        asleep.len(),
        mean(&overlap),
        overlap.iter().copied().fold(0.0, f32::max)
    );
    assert!(
        restless.is_empty(),
        "{} of {} piles still moving after 10 s: {restless:?}",
        restless.len(),
        ends.len()
    );
    assert!(
        mean(&overlap) < 1.0,
        "mean overlap at rest {} mm",
        mean(&overlap)
    );
    let deepest = overlap.iter().copied().fold(0.0, f32::max);
    assert!(deepest < 2.0, "a pile overlaps by {deepest} mm at rest");
}

/// Joint damping's part: at the variant's 0.2 N m s/rad the piles of layouts 1-64 x both
/// spines come to rest at least as often, and fall asleep sooner on average, than at half of
/// it. A survey of 256 runs, so not run by default.
#[test]
#[ignore = "a survey of 256 drops of 10 s (about 80 s on 2 cores): cargo test --release \
            --test it -- --ignored ragdoll_drop::game::joint_damping --nocapture"]
fn joint_damping_brings_the_piles_to_rest_sooner() {
    let _alone = one_at_a_time();
    // (layouts at rest, the mean frame from which the whole pile sleeps) at the variant's
    // damping, then at 0.1
    let [(at_rest, asleep_from), (at_rest_half, asleep_from_half)] =
        [None, Some(0.1)].map(|joint_damping| {
            let overrides = Overrides {
                joint_damping,
                ..Default::default()
            };
            let ends: Vec<_> = (survey("game", &overrides).into_iter())
                .map(|r| r.end.expect("no explosion"))
                .collect();
            let still = ends.iter().filter(|e| e.still_moving == 0).count();
            let frames: Vec<f32> = (ends.iter())
                .filter_map(|e| e.all_asleep_from.map(|f| f as f32))
                .collect();
            (still, mean(&frames))
        });
    let n = SURVEY_RUNS;
    println!(
        "at rest after 10 s: {at_rest} of {n} layouts, all asleep from frame {asleep_from:.0} on \
         average; at half the joint damping {at_rest_half}, from frame {asleep_from_half:.0}"
    );
    assert!(
        at_rest >= at_rest_half,
        "{at_rest} against {at_rest_half} of {n}"
    );
    assert!(
        asleep_from < asleep_from_half,
        "asleep from frame {asleep_from} on average, {asleep_from_half} at half the damping"
    );
}
