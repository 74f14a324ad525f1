//! The drop at rest (issue 10): the scene's `at_rest` variant on its layout, and as a rate
//! over layouts 1-64 x both spines.

use super::*;
use rodlab::sim;

/// The drop at its `at_rest` variant on layout `seed` with one spine; returns the final lab and
/// the run's report.
fn drop_at_rest(seed: u64, spine: SpineKind) -> (Lab, sim::RunReport) {
    let (scene, mut lab) = drop_lab(Some("at_rest"), &spine_and_seed(spine, seed));
    assert!(scene.def.sleep && scene.def.joint_damping > 0.0);
    let report = sim::run(&mut lab, scene.def.frames, &mut sim::NoObserver).unwrap();
    (lab, report)
}

/// The drop at rest (issue 10): at the scene's `at_rest` variant (4 substeps of 4 iterations,
/// SIMD, exact joints, contacts warm-started at 0.25 and soft at 60 Hz, joint damping 0.2
/// N m s/rad (0.1 until stop 47), sleeping on) the pile is asleep, or has every surface point
/// under the sleep speed, after its 10 s, with either spine, on the scene's layout (seed 7)
/// and seeds 1-3. With one row along a hinge's error 7 of the 26 piles of seeds 7 and 1-13 x
/// both spines were still awake at frame 600, their limbs twisting back and forth every
/// substep across an elbow; since the exact flavour aligns a hinge's axes as one 2x2 block, 0,
/// 0 and 3 of the 26 in three builds that differ only in rounding, the 3 moved by late slides
/// in the pile (docs/benchmarks.md, stop 35). Layout 6 (rod) is the trapped forearm's (docs/solver.md, Push
/// speed): without the variant's 5 m/s push speed one ragdoll flails on the floor to the end.
/// At rest the overlapping contact points overlap by under 2 mm on average (measured 0.63 mm
/// chain3, 0.85 mm rod; 2.8-2.9 mm with 30 Hz contacts, which sink further under a pile).
#[test]
fn the_drop_pile_falls_asleep_at_the_scenes_at_rest_variant() {
    use rodlab::sleep::SLEEP_SPEED;
    let _alone = one_at_a_time();
    let seeds = [7, 1, 2, 3, 6];
    let layouts = seeds
        .iter()
        .flat_map(|&s| [SpineKind::Chain3, SpineKind::Rod].map(|p| (s, p)));
    for (seed, spine) in layouts {
        let (lab, report) = drop_at_rest(seed, spine);
        let dynamic = lab.world.bodies.iter().filter(|b| b.is_dynamic()).count();
        let asleep = lab.world.bodies.iter().filter(|b| b.is_asleep()).count();
        let first_all_asleep = report.awake_bodies.iter().position(|&n| n == 0);
        let still_moving: Vec<_> = (report.restless.iter())
            .map(|(n, r)| (n, r.point_speed))
            .collect();
        println!(
            "seed {seed}, {spine}: {asleep} of {dynamic} bodies asleep after 10 s, all from frame \
             {first_all_asleep:?}; still moving: {still_moving:?}"
        );
        assert!(
            report.restless.is_empty(),
            "seed {seed}, {spine}: bodies still moving at or over {SLEEP_SPEED} m/s after 10 s: {:?}",
            report.restless
        );
        let (overlapping, points, mean) = lab.world.overlap_at_rest();
        println!(
            "seed {seed}, {spine}: at rest {overlapping} of {points} contact points overlap, by {:.2} mm on average",
            1000.0 * mean
        );
        assert!(overlapping > 100, "the pile has too few contacts to judge");
        assert!(
            mean < 2e-3,
            "seed {seed}, {spine}: mean penetration at rest {mean} m (issue 10: 2 mm)"
        );
    }
}

/// Issue 10's drop at rest as a rate over many layouts rather than a few samples: the pile
/// comes to rest in 10 s on nearly every layout at the `at_rest` variant's joint damping
/// (0.2 N m s/rad), and falls asleep sooner on average than at half of it. Measured over
/// layouts 1-64 x both spines: 126 of 128 at rest, all asleep from frame 372 on average,
/// against 123 of 128 from frame 414 at 0.1 (docs/solver.md, Joint damping for the pile at
/// rest). A survey of 256 runs of 10 s, so not run by default.
#[test]
#[ignore = "a survey of 256 drops of 10 s (about 2 min on 2 cores): cargo test --release \
            --test it -- --ignored ragdoll_drop::at_rest::the_at_rest_drop_comes_to_rest_on_nearly_every_layout \
            --nocapture; each layout's row: rodlab layouts scenes/ragdoll_drop.toml --variant at_rest \
            --seeds 1-64"]
fn the_at_rest_drop_comes_to_rest_on_nearly_every_layout() {
    let _alone = one_at_a_time();
    // (layouts at rest, the mean frame from which the whole pile sleeps) at the variant's
    // damping, then at 0.1
    let [(at_rest, asleep_from), (at_rest_half, asleep_from_half)] =
        [None, Some(0.1)].map(|joint_damping| {
            let overrides = Overrides {
                joint_damping,
                ..Default::default()
            };
            let ends: Vec<_> = (survey("at_rest", &overrides).into_iter())
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
    assert!(20 * at_rest >= 19 * n, "{at_rest} of {n} at rest");
    assert!(
        asleep_from < asleep_from_half,
        "asleep from frame {asleep_from} on average, {asleep_from_half} at half the damping"
    );
}
