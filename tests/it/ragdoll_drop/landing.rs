//! The landing within 1 cm: contacts found every substep, swept alone after each substep's
//! iterations, as rates over layouts (each landing is one sample of a chaotic pile), and the
//! landing a forearm once exploded on, pinned by its state hash.

use super::*;
use rodlab::sim;
use rodlab::world::{ContactDetection, SolverKind};

/// The 1 cm as a rate over many landings: the tight method, its stacking ratio
/// capped at e, keeps the deepest overlap of the landing (150 frames) within 1 cm on nearly
/// every layout of 1-64 x both spines and rarely explodes, and its landings are shallower on
/// average than the same variant's uncapped. A survey of 256 runs, so not run by default.
#[test]
#[ignore = "a survey of 256 landings (about 3 min on 2 cores): cargo test --release --test it \
            -- --ignored ragdoll_drop::landing::the_capped_ratio_keeps_nearly_every_landing_within_a_centimetre \
            --nocapture; each layout's row: rodlab layouts scenes/ragdoll_drop.toml --variant \
            tight --seeds 1-64 --frames 150"]
fn the_capped_ratio_keeps_nearly_every_landing_within_a_centimetre() {
    let _alone = one_at_a_time();
    // (over 1 cm, exploded, mean deepest overlap in cm) with the variant's cap, then without one
    let failures = [None, Some(f32::INFINITY)].map(|max_ratio| {
        let overrides = Overrides {
            contact_stacking_max_ratio: max_ratio,
            frames: Some(150),
            ..Default::default()
        };
        let runs = survey("tight", &overrides);
        let ends: Vec<_> = runs.iter().filter_map(|r| r.end.as_ref().ok()).collect();
        let deep = ends.iter().filter(|e| e.deepest_overlap_cm > 1.0).count();
        let deepest: Vec<f32> = ends.iter().map(|e| e.deepest_overlap_cm).collect();
        (deep, runs.len() - ends.len(), mean(&deepest))
    });
    let n = SURVEY_RUNS;
    println!(
        "of {n} landings, (over 1 cm, exploded, mean deepest cm): capped {:?}, uncapped {:?}",
        failures[0], failures[1]
    );
    let [(deep, exploded, capped_mean), (_, _, uncapped_mean)] = failures;
    assert!(deep <= 2 && exploded <= 2, "capped: {failures:?} of {n}");
    assert!(capped_mean < uncapped_mean, "{failures:?} of {n}");
}

/// The drop's landing (frames 0-150) over layouts 1-8 x both spines at `variant` (`None`: the
/// paper's method) with `overrides`: each run's deepest overlap found afresh on each frame's
/// final poses (cm), chain3's runs then rod's, in seed order.
fn landing_overlaps(variant: Option<&str>, overrides: Overrides) -> [Vec<f32>; 2] {
    let _alone = one_at_a_time();
    let seeds: Vec<u64> = (1..=8).collect();
    let overrides = Overrides {
        frames: Some(150),
        ..overrides
    };
    let runs = rodlab::sweep::layouts::run_layouts(
        SCENE.as_ref(),
        variant,
        &overrides,
        &seeds,
        &[SpineKind::Chain3, SpineKind::Rod],
        |_| {},
    )
    .unwrap();
    [SpineKind::Chain3, SpineKind::Rod].map(|spine| {
        let of = runs.iter().filter(|r| r.spine == spine);
        of.map(|r| r.end.as_ref().expect("no explosion").deepest_overlap_cm)
            .collect()
    })
}

/// Contact points found once a frame keep their normals and body-space points through the
/// substeps, while limbs slide and roll over each other: a detection on each frame's final
/// poses finds overlaps the points no longer see. Found afresh every substep, the points follow
/// the features that touch. At 4 substeps of 5 iterations, over layouts 1-8 x both spines: the
/// deepest overlap of the landing is lower every substep on at least 6 of each spine's 8
/// layouts, and under 0.8 times once a frame's on their mean.
#[test]
fn detecting_contacts_every_substep_leaves_less_overlap_than_once_a_frame() {
    let at = |contact_detection| Overrides {
        substeps: Some(4),
        iterations: Some(5),
        contact_detection: Some(contact_detection),
        ..Default::default()
    };
    let once = landing_overlaps(None, at(ContactDetection::Frame));
    let every = landing_overlaps(None, at(ContactDetection::Substep));
    for (k, spine) in ["chain3", "rod"].into_iter().enumerate() {
        let lower = once[k].iter().zip(&every[k]).filter(|(o, e)| e < o).count();
        let (once_mean, every_mean) = (mean(&once[k]), mean(&every[k]));
        println!(
            "{spine}: deepest overlap of the landing per layout, once a frame {:.2?} cm, every \
             substep {:.2?} cm; lower on {lower} of 8, means {once_mean:.2} / {every_mean:.2} cm",
            once[k], every[k]
        );
        assert!(
            lower >= 6,
            "{spine}: every substep lower on only {lower} of 8 layouts"
        );
        assert!(
            every_mean < 0.8 * once_mean,
            "{spine}: mean deepest {every_mean} cm every substep, {once_mean} cm once a frame"
        );
    }
}

/// The 1 cm: the tight method's contacts, solved alone after each substep's joint
/// sweep, push out what that sweep left, so over layouts 1-8 x both spines at most one landing
/// of each spine passes 1 cm, and the mean deepest overlap is under half of the same method's
/// without those sweeps.
#[test]
fn extra_contact_sweeps_keep_the_drops_landing_within_a_centimetre() {
    let plain = landing_overlaps(
        Some("tight"),
        Overrides {
            contact_extra_sweeps: Some(0),
            ..Default::default()
        },
    );
    let swept = landing_overlaps(Some("tight"), Overrides::default());
    for (k, spine) in ["chain3", "rod"].into_iter().enumerate() {
        let deep = swept[k].iter().filter(|&&d| d > 1.0).count();
        let (plain_mean, swept_mean) = (mean(&plain[k]), mean(&swept[k]));
        println!(
            "{spine}: deepest overlap of the landing per layout, without extra contact sweeps \
             {:.2?} cm, with the variant's {:.2?} cm; means {plain_mean:.2} / {swept_mean:.2} cm",
            plain[k], swept[k]
        );
        assert!(deep <= 1, "{spine}: {deep} of 8 landings over 1 cm");
        assert!(
            swept_mean < 0.5 * plain_mean,
            "{spine}: mean deepest {swept_mean} cm with the sweeps, {plain_mean} cm without"
        );
    }
}

/// Layout 52's rod pile, where cheap joints with three contact sweeps once threw a forearm
/// pressed between two other ragdolls past the explosion bound (the one-row hinge turning it
/// about its own axis back and forth every substep): at the tight method (exact
/// joints, whose hinge aligns its axes as one block, and six sweeps), with either row solver,
/// the landing runs its 150 frames within 1 cm, and ends in its committed state (one pile is a
/// chaotic sample: the hash pins it exactly).
#[test]
fn the_landing_a_forearm_exploded_on_holds_with_exact_joints() {
    let _alone = one_at_a_time();
    for (solver, hash) in [
        (SolverKind::Scalar, 0xc35a_974c_2281_c7dcu64),
        (SolverKind::Simd, 0xe692_3476_98be_e378),
    ] {
        let overrides = Overrides {
            spine: Some(SpineKind::Rod),
            seed: Some(52),
            frames: Some(150),
            solver: Some(solver),
            ..Default::default()
        };
        let (_, mut lab) = drop_lab(Some("tight"), &overrides);
        let report = sim::run(&mut lab, 150, &mut sim::NoObserver).expect("no explosion");
        let deepest = report.max_overlap_cm;
        println!("{solver}: deepest overlap {deepest:.2} cm");
        assert!(deepest <= 1.0, "{solver}: {deepest} cm");
        crate::common::assert_state_hash(
            &format!("layout 52 rod, {solver}"),
            report.state_hash,
            hash,
        );
    }
}
