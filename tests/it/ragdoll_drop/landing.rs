//! The landing within 1 cm (issue 10): contacts found every substep, swept alone after each
//! substep's iteration, and the landings a survey of 256 keeps.

use super::*;
use rodlab::constraint::JointFlavour;
use rodlab::lab::Lab;
use rodlab::sim;
use rodlab::world::{ContactDetection, SolverKind};

/// Issue 10's 1 cm as a rate over many landings: the `redetect_sweeps` variant, its stacking
/// ratio capped at e, keeps the deepest overlap of the landing (150 frames) within 1 cm on
/// nearly every layout and rarely explodes, and fails fewer layouts than the same variant
/// uncapped. Measured over layouts 1-64 x both spines: capped 0 over 1 cm and no explosion,
/// uncapped 1 and none (SIMD, the variant's solver since stop 48; scalar: 0 and 0, uncapped 2,
/// 3.85 and 2.34 cm, and 0); before the variant's exact joints and six sweeps
/// (stop 46: cheap joints, three sweeps) capped 0 and 1 (layout 52, rod), uncapped 7 and 4
/// (docs/solver.md, Landings that hold). A survey of 256 runs, so not run by default.
#[test]
#[ignore = "a survey of 256 landings (about 3 min on 2 cores): cargo test --release --test it \
            -- --ignored ragdoll_drop::landing::the_capped_ratio_keeps_nearly_every_landing_within_a_centimetre \
            --nocapture; each layout's row: rodlab layouts scenes/ragdoll_drop.toml --variant \
            redetect_sweeps --seeds 1-64 --frames 150"]
fn the_capped_ratio_keeps_nearly_every_landing_within_a_centimetre() {
    let _alone = one_at_a_time();
    // (over 1 cm, exploded) with the variant's cap, then without one
    let failures = [None, Some(f32::INFINITY)].map(|max_ratio| {
        let overrides = Overrides {
            contact_stacking_max_ratio: max_ratio,
            frames: Some(150),
            ..Default::default()
        };
        let runs = survey("redetect_sweeps", &overrides);
        let deep = (runs.iter())
            .filter(|r| r.end.as_ref().is_ok_and(|e| e.deepest_overlap_cm > 1.0))
            .count();
        (deep, runs.iter().filter(|r| r.end.is_err()).count())
    });
    let n = SURVEY_RUNS;
    println!(
        "of {n} landings, (over 1 cm, exploded): capped {:?}, uncapped {:?}",
        failures[0], failures[1]
    );
    let [(deep, exploded), (deep_uncapped, exploded_uncapped)] = failures;
    assert!(deep <= 2 && exploded <= 2, "capped: {failures:?} of {n}");
    assert!(
        deep + exploded < deep_uncapped + exploded_uncapped,
        "{failures:?} of {n}"
    );
}

/// The drop's landing (frames 0-150) at 4 substeps of 5 iterations, with contacts found once a
/// frame (the paper's detection) or afresh every substep, for one spine: (the mean over frames
/// of each frame's deepest overlap found afresh, the deepest over the run), cm.
fn landing_overlap(spine: SpineKind, detection: ContactDetection) -> (f32, f32) {
    let (mut lab, frames) = crate::common::lab_with(
        "ragdoll_drop",
        Overrides {
            spine: Some(spine),
            substeps: Some(4),
            iterations: Some(5),
            contact_detection: Some(detection),
            frames: Some(150),
            ..Default::default()
        },
    );
    let mut per_frame = Vec::new();
    let mut observer =
        |_: &Lab, m: &rodlab::metrics::FrameMetrics| per_frame.push(m.max_overlap_cm);
    let report = sim::run(&mut lab, frames, &mut observer).unwrap();
    (mean(&per_frame), report.max_overlap_cm)
}

/// Contact points found once a frame keep their normals and body-space points through the
/// substeps, while limbs slide and roll over each other: a detection on each frame's final
/// poses finds overlaps the points no longer see. Found afresh every substep, the points follow
/// the features that touch. The deepest overlap over a landing is a chaotic extreme, so the
/// bound is loose: measured over layouts 7 / 1 / 2 / 3 (4 x 5, 300 frames, a probe not kept;
/// docs/solver.md), once a frame 5.3 / 5.9 / 5.7 / 6.5 cm chain3 and 6.0 / 7.5 / 4.7 / 5.2 cm
/// rod, every substep 3.6 / 3.7 / 3.6 / 3.9 and 4.2 / 2.8 / 2.5 / 2.8 cm: 0.37-0.70 times.
#[test]
fn detecting_contacts_every_substep_leaves_less_overlap_than_once_a_frame() {
    let _alone = one_at_a_time();
    for spine in [SpineKind::Chain3, SpineKind::Rod] {
        let (frame_mean, frame_deepest) = landing_overlap(spine, ContactDetection::Frame);
        let (substep_mean, substep_deepest) = landing_overlap(spine, ContactDetection::Substep);
        println!(
            "{spine}: deepest overlap found afresh over frames 0-150, {frame_deepest:.2} cm once \
             a frame, {substep_deepest:.2} cm every substep (mean of each frame's deepest \
             {frame_mean:.3} / {substep_mean:.3} cm)"
        );
        assert!(
            substep_deepest < 0.8 * frame_deepest,
            "{spine}: deepest overlap {substep_deepest} cm every substep, {frame_deepest} cm \
             once a frame"
        );
    }
}

/// The drop's `redetect_sweeps` variant (20 substeps of one iteration, contacts found every
/// substep, then six sweeps of the contacts alone) for one spine over the landing, frames
/// 0-150, with `extra_sweeps` in place of its six (`None`: its own): (the mean over frames of
/// each frame's deepest overlap found afresh, the deepest over the run), cm.
fn landing_overlap_with_sweeps(spine: SpineKind, extra_sweeps: Option<u32>) -> (f32, f32) {
    let overrides = Overrides {
        spine: Some(spine),
        contact_extra_sweeps: extra_sweeps,
        frames: Some(150),
        ..Default::default()
    };
    let (_, mut lab) = drop_lab(Some("redetect_sweeps"), &overrides);
    let mut per_frame = Vec::new();
    let mut observer =
        |_: &Lab, m: &rodlab::metrics::FrameMetrics| per_frame.push(m.max_overlap_cm);
    let report = sim::run(&mut lab, 150, &mut observer).unwrap();
    (mean(&per_frame), report.max_overlap_cm)
}

/// Issue 10's 1 cm: the contacts solved alone after each substep's joint sweep push out what
/// that sweep left, so the landing stays within a centimetre for both spines (over the whole
/// 10 s and layouts 7 / 1 / 2 / 3 the deepest is 0.08-0.17 cm, and 0.71 cm on layout 2's rod
/// pile, `rodlab layouts scenes/ragdoll_drop.toml --variant redetect_sweeps --seeds 1-3,7`);
/// here 0.17 / 0.13 cm (chain3 / rod) where the same method without them lets 0.60 / 1.05 cm
/// through; and each frame's deepest overlap is smaller on average (0.006-0.007 against
/// 0.07 cm). With the scalar solver, the variant's until stop 48: 0.06 / 0.13 against
/// 0.63 / 1.76 cm.
#[test]
fn extra_contact_sweeps_keep_the_drops_landing_within_a_centimetre() {
    let _alone = one_at_a_time();
    for spine in [SpineKind::Chain3, SpineKind::Rod] {
        let (plain_mean, plain_deepest) = landing_overlap_with_sweeps(spine, Some(0));
        let (swept_mean, swept_deepest) = landing_overlap_with_sweeps(spine, None);
        println!(
            "{spine}: deepest overlap found afresh over frames 0-150, {plain_deepest:.2} cm \
             without extra contact sweeps, {swept_deepest:.2} cm with the variant's (mean of each \
             frame's deepest {plain_mean:.3} / {swept_mean:.3} cm)"
        );
        assert!(swept_deepest <= 1.0, "{spine}: {swept_deepest} cm");
        assert!(
            swept_mean < 0.8 * plain_mean,
            "{spine}: mean deepest {swept_mean} cm with the sweeps, {plain_mean} cm without"
        );
    }
}

/// Stop 46's explosion kept as a case (docs/solver.md, Landings that hold): at stop 46's
/// `redetect_sweeps` (the paper's cheap joints, three contact sweeps, the scalar solver;
/// printed, not asserted, as one pile is a chaotic sample), layout 52's rod pile threw a
/// forearm pressed between two other ragdolls past 500 rad/s at frame 82, the one-row hinge
/// turning it about its own axis back and forth every substep. At the variant (exact joints,
/// whose hinge aligns its axes as one block, and six sweeps), with either row solver, the same
/// landing runs its 150 frames within 1 cm (measured 0.07 cm scalar, 0.07 cm SIMD).
#[test]
fn the_landing_whose_forearm_exploded_with_cheap_joints_holds_with_exact_ones() {
    let _alone = one_at_a_time();
    let landing = |solver: SolverKind,
                   joint_flavour: Option<JointFlavour>,
                   contact_extra_sweeps: Option<u32>| {
        let overrides = Overrides {
            spine: Some(SpineKind::Rod),
            seed: Some(52),
            frames: Some(150),
            solver: Some(solver),
            joint_flavour,
            contact_extra_sweeps,
            ..Default::default()
        };
        let (_, mut lab) = drop_lab(Some("redetect_sweeps"), &overrides);
        sim::run(&mut lab, 150, &mut sim::NoObserver).map(|r| r.max_overlap_cm)
    };
    // stop 46's variant: cheap joints, three sweeps (an explosion, printed, not asserted: one
    // pile is a chaotic sample)
    let cheap = landing(SolverKind::Scalar, Some(JointFlavour::Cheap), Some(3));
    println!("stop 46's variant, cheap joints and three sweeps: {cheap:?}");
    for solver in [SolverKind::Scalar, SolverKind::Simd] {
        let deepest =
            landing(solver, None, None).expect("no explosion with the variant's exact joints");
        println!("{solver}, the variant's exact joints: deepest overlap {deepest:.2} cm");
        assert!(deepest <= 1.0, "{solver}: {deepest} cm");
    }
}
