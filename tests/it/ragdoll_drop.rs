//! The 30-ragdoll drop (paper Fig. 1, bottom of Fig. 8): ten seconds without NaN, nothing
//! through the floor, every body nearly at rest at the end, and the rod spine leaving less
//! dislocation than the three-joint spine: on the mean over four layouts, and on at least 80%
//! of all their frames. The contacts issue's 90% is held with stacking, the paper's method
//! with contacts that carry the pile's weight (`with_stacking_the_rod_spine_is_lower...`).

use rodlab::cli::load_scene;
use rodlab::constraint::JointFlavour;
use rodlab::lab::Lab;
use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::sim::{self, Overrides};
use rodlab::world::ContactDetection;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ragdoll_drop.toml");

/// The tests of this file run one at a time: they share rayon's global pool, and a step
/// waiting for the other test's work to leave the pool spends that wait outside every profiled
/// phase (the profile test measured 80% of its stepping time in phases when they overlapped).
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Runs the drop with one spine and layout seed; returns the final lab, the total dislocation
/// (cm) per frame and the lowest body centre (m).
fn drop(spine: SpineKind, seed: u64) -> (Lab, Vec<f32>, f32) {
    let overrides = Overrides {
        spine: Some(spine),
        seed: Some(seed),
        ..Default::default()
    };
    let scene = load_scene(SCENE.as_ref(), None, &overrides).unwrap();
    let mut lab = scene.build().unwrap();
    assert_eq!(lab.ragdolls.len(), 30);
    let mut lowest = f32::INFINITY;
    let mut observer = |lab: &Lab, _: &rodlab::metrics::FrameMetrics| {
        for r in &lab.ragdolls {
            for id in r.body_ids() {
                let body = lab.world.body(id);
                lowest = lowest.min(body.position.y);
            }
        }
    };
    let report = sim::run(&mut lab, scene.def.frames, &mut observer).expect("no NaN, no explosion");
    (lab, report.total_dislocation_cm, lowest)
}

fn mean(values: &[f32]) -> f32 {
    values.iter().sum::<f32>() / values.len() as f32
}

/// How still a drop's pile is at its end: the fastest body centre and the fastest surface
/// point (m/s), and the fraction of bodies with every point under 0.2 m/s.
fn stillness(lab: &Lab) -> (f32, f32, f32) {
    let bodies: Vec<_> = (lab.ragdolls.iter())
        .flat_map(|r| r.body_ids())
        .map(|id| lab.world.body(id))
        .collect();
    let fastest_centre = (bodies.iter())
        .map(|b| b.linear_velocity.length())
        .fold(0.0, f32::max);
    let point_speeds: Vec<f32> = bodies.iter().map(|b| b.max_point_speed()).collect();
    let fastest_point = point_speeds.iter().copied().fold(0.0, f32::max);
    let resting =
        point_speeds.iter().filter(|&&v| v < 0.2).count() as f32 / point_speeds.len() as f32;
    (fastest_centre, fastest_point, resting)
}

fn median(mut values: Vec<f32>) -> f32 {
    values.sort_by(f32::total_cmp);
    let n = values.len();
    0.5 * (values[(n - 1) / 2] + values[n / 2])
}

#[test]
fn thirty_ragdolls_land_and_settle_and_the_rod_spine_leaves_less_residual() {
    let _alone = one_at_a_time();
    // per spine (chain3, rod): each layout's mean total dislocation, per-frame dislocation and
    // stillness at the end
    let mut means = [0.0f32; 2];
    let mut per_frame: [Vec<Vec<f32>>; 2] = Default::default();
    let mut still: [Vec<(f32, f32, f32)>; 2] = Default::default();
    for seed in [7, 1, 2, 3] {
        for (k, spine) in [SpineKind::Chain3, SpineKind::Rod].into_iter().enumerate() {
            let (lab, dislocation, lowest) = drop(spine, seed);
            // body centres stay above the floor (the thinnest limb has a 4 cm radius)
            assert!(lowest > 0.0, "{spine}: a body centre reached y = {lowest}");
            let (centre, point, resting) = stillness(&lab);
            println!(
                "seed {seed}, {spine}: mean total dislocation {:.1} cm; at the end fastest \
                 centre {centre:.3} m/s, fastest point {point:.3} m/s, {:.1}% of bodies with \
                 every point under 0.2 m/s",
                mean(&dislocation),
                100.0 * resting
            );
            means[k] += mean(&dislocation);
            per_frame[k].push(dislocation);
            still[k].push((centre, point, resting));
        }
    }
    // Nearly at rest: a few limbs caught between stair boxes and other ragdolls still twitch
    // about their long axis. Each pile is one chaotic sample (these figures move with the
    // order contacts are solved in and with any change to the box's points), so the medians
    // over the four layouts are held to the bounds and each layout to looser ones. Measured
    // (seeds 7 / 1 / 2 / 3) since the box's nearest point is exact: fastest centre
    // 0.29 / 0.19 / 0.35 / 0.29 m/s chain3 and 0.40 / 0.22 / 0.08 / 0.08 rod; fastest point
    // 0.58 / 0.31 / 0.93 / 0.59 and 1.32 / 0.61 / 0.39 / 0.24 m/s; at rest 99.0 / 98.5 / 95.9
    // / 99.7% and 93.3 / 97.3 / 97.0 / 99.7%. Before it seed 7 alone was held to the bounds
    // (rod 0.30 m/s, 1.17 m/s, 94.5%); over layouts 1-16 the two builds' piles twitch alike
    // (fastest point 0.60 and 0.55 m/s on average, `rodlab layouts scenes/ragdoll_drop.toml
    // --seeds 1-16`).
    for (k, spine) in ["chain3", "rod"].into_iter().enumerate() {
        let centre = median(still[k].iter().map(|s| s.0).collect());
        let point = median(still[k].iter().map(|s| s.1).collect());
        let resting = median(still[k].iter().map(|s| s.2).collect());
        assert!(
            centre < 0.35,
            "{spine}: the median layout's fastest centre moves at {centre} m/s after 10 s"
        );
        assert!(
            point < 1.5,
            "{spine}: the median layout's fastest surface point moves at {point} m/s"
        );
        assert!(
            resting > 0.94,
            "{spine}: the median layout has only {:.1}% of bodies at rest",
            100.0 * resting
        );
        for &(centre, point, resting) in &still[k] {
            assert!(
                centre < 0.6 && point < 2.0 && resting > 0.9,
                "{spine}: {still:?}"
            );
        }
    }
    // The paper's result over four layouts: one pile is a chaotic sample (measured, seeds
    // 7 / 1 / 2 / 3: chain3 58.4 / 54.9 / 51.4 / 52.7 cm, rod 46.4 / 42.8 / 47.6 / 40.0 cm),
    // so the means over the layouts are compared, and the frames of all four where the rod is
    // lower are counted. Measured: 2119 of 2400 (88.3%; 2308, 96.2%, before the box's exact
    // nearest point); in the broad phase's earlier cell
    // order 2030 (84.6%: seed 3's settled rod pile sat above its chain3), and 97% before the
    // speculative reach counted spin. One layout flips with small changes to contacts, so the
    // bound stays at 80% here; the 90% is held at the stacked variant (below).
    let (mut lower, mut frames) = (0, 0);
    for (chain3, rod) in per_frame[0].iter().zip(&per_frame[1]) {
        lower += chain3.iter().zip(rod).filter(|(c, r)| r < c).count();
        frames += chain3.len();
    }
    println!(
        "rod below chain3 on {lower} of {frames} frames ({:.1}%)",
        100.0 * lower as f32 / frames as f32
    );
    assert!(
        means[1] < 0.9 * means[0],
        "mean total dislocation over four layouts: rod {} cm vs chain3 {} cm",
        means[1] / 4.0,
        means[0] / 4.0
    );
    assert!(
        lower as f32 >= 0.8 * frames as f32,
        "rod below chain3 on only {lower} of {frames} frames"
    );
}

/// The step profile accounts for the step: every phase the drop runs takes time, and the
/// phases add up to the step's own wall time, timed where the step runs (`Profile::step`).
/// The caller's time around `World::step` is not the yardstick: it adds the hand-over onto
/// rayon's pool, whose wake-up latency on a loaded 2-core machine ranged up to a quarter of a
/// 2 ms step (CI measured 76% of it in phases), and that says nothing about the profile.
#[test]
fn the_step_profile_accounts_for_the_step() {
    let _alone = one_at_a_time();
    let mut lab = Scene::load(SCENE).unwrap().build().unwrap();
    // one untimed frame first: the first step starts rayon's threads
    sim::run(&mut lab, 1, &mut sim::NoObserver).unwrap();
    let report = sim::run(&mut lab, 20, &mut sim::NoObserver).unwrap();
    let p = report.profile;
    for (name, seconds) in p.phases() {
        let runs = name != "rods" && name != "sleep"; // chain3 spines: no rods; sleep is off
        assert!(!runs || seconds > 0.0, "{name}: {seconds} s");
    }
    let (total, step, outside) = (p.total(), p.step, report.step_seconds);
    println!("profile {total:.6} s of {step:.6} s stepping ({outside:.6} s around the calls)");
    assert!(total <= step, "phases {total} s exceed the step's {step} s");
    assert!(
        step <= outside,
        "the step's {step} s exceed the {outside} s around it"
    );
    assert!(
        total > 0.95 * step,
        "phases {total} s of the step's {step} s: a part of the step is in no phase"
    );
}

/// Detection's pieces (`Contacts::detection_profile`) lie within the step's detect phase, and
/// the broad and narrow phases' parts within them; a new world's first detection rebuilds its
/// pairs, and every body pair with a point was tested.
#[test]
fn the_detection_profile_accounts_for_detection() {
    let _alone = one_at_a_time();
    let mut lab = Scene::load(SCENE).unwrap().build().unwrap();
    lab.step().unwrap();
    let first = *lab.world.contacts.detection_profile();
    assert!(
        first.rebuilt,
        "a new world's first detection rebuilds: {first:?}"
    );
    sim::run(&mut lab, 90, &mut sim::NoObserver).unwrap(); // the pile has formed
    for _ in 0..20 {
        lab.step().unwrap();
        let d = *lab.world.contacts.detection_profile();
        // the broad phase and the handover run side by side on two threads, one after the
        // other on one
        let pieces = d.records + d.broad_phase.max(d.handover) + d.narrow_phase + d.concatenate;
        let detect = lab.world.solver.profile.detect;
        assert!(
            pieces <= detect,
            "pieces {pieces} s of detect's {detect} s: {d:?}"
        );
        // the broad phase's parts lie within it; the narrow phase's work, summed over its
        // threads, within its wall time on each thread, and some of it goes to every part
        let broad = d.broad_phase_parts;
        assert!(broad.boxes > 0.0 && broad.pairs > 0.0, "{d:?}");
        assert!(broad.boxes + broad.pairs <= d.broad_phase, "{d:?}");
        let work = d.narrow_phase_work;
        let threads = rayon::current_num_threads() as f64;
        assert!(
            work.report > 0.0 && work.shape_tests > 0.0 && work.points > 0.0,
            "{d:?}"
        );
        assert!(
            work.report + work.shape_tests + work.points <= threads * d.narrow_phase,
            "{d:?}"
        );
        let mut pairs: Vec<(u32, u32)> = (lab.world.contacts.points.iter())
            .map(|p| (p.body_a.0, p.body_b.0))
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        assert!(!pairs.is_empty(), "the pile touches");
        assert!(
            pairs.len() <= d.pairs_tested,
            "{} pairs with points, {} tested",
            pairs.len(),
            d.pairs_tested
        );
    }
}

/// The drop at its `at_rest` variant on layout `seed` with one spine; returns the final lab and
/// the run's report.
fn drop_at_rest(seed: u64, spine: SpineKind) -> (Lab, sim::RunReport) {
    let overrides = Overrides {
        spine: Some(spine),
        seed: Some(seed),
        ..Default::default()
    };
    let scene = load_scene(SCENE.as_ref(), Some("at_rest"), &overrides).unwrap();
    assert!(scene.def.sleep && scene.def.joint_damping > 0.0);
    let mut lab = scene.build().unwrap();
    let report = sim::run(&mut lab, scene.def.frames, &mut sim::NoObserver).unwrap();
    (lab, report)
}

/// The drop at rest (issue 10): at the scene's `at_rest` variant (4 substeps of 4 iterations,
/// SIMD, exact joints, contacts warm-started at 0.25 and soft at 60 Hz, joint damping 0.2
/// N m s/rad (0.1 until stop 47), sleeping on) the pile is asleep, or has every surface point under the sleep
/// speed, after its 10 s, with either spine, on the scene's layout (seed 7) and seeds 1-3. With
/// one row along a hinge's error 7 of the 26 piles of seeds 7 and 1-13 x both spines were still
/// awake at frame 600, their limbs twisting back and forth every substep across an elbow; since
/// the exact flavour aligns a hinge's axes as one 2x2 block, 0, 0 and 3 of the 26 in three
/// builds that differ only in rounding, the 3 moved by late slides in the pile
/// (docs/benchmarks.md, stop 35). Layout 6 (rod) is the trapped forearm's (docs/solver.md, Push
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
        println!("seed {seed}, {spine}: {asleep} of {dynamic} bodies asleep after 10 s, all from frame {first_all_asleep:?}; still moving: {:?}", report.restless.iter().map(|(n, r)| (n, r.point_speed)).collect::<Vec<_>>());
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

/// The layouts the surveys below run: seeds 1-64, both spines (128 runs).
const SURVEY_RUNS: usize = 128;

/// The scene's `variant` with `overrides` on layouts 1-64 x both spines.
fn survey(variant: &str, overrides: &Overrides) -> Vec<rodlab::sweep::layouts::LayoutRun> {
    let seeds: Vec<u64> = (1..=64).collect();
    let spines = [SpineKind::Chain3, SpineKind::Rod];
    let runs = rodlab::sweep::layouts::run_layouts(
        SCENE.as_ref(),
        Some(variant),
        overrides,
        &seeds,
        &spines,
        |_| {},
    )
    .unwrap();
    assert_eq!(runs.len(), SURVEY_RUNS);
    runs
}

/// Issue 10's drop at rest as a rate over many layouts rather than a few samples: the pile
/// comes to rest in 10 s on nearly every layout at the `at_rest` variant's joint damping
/// (0.2 N m s/rad), and falls asleep sooner on average than at half of it. Measured over
/// layouts 1-64 x both spines: 126 of 128 at rest, all asleep from frame 372 on average,
/// against 123 of 128 from frame 414 at 0.1 (docs/solver.md, Joint damping for the pile at
/// rest). A survey of 256 runs of 10 s, so not run by default.
#[test]
#[ignore = "a survey of 256 drops of 10 s (about 2 min on 2 cores): cargo test --release \
            --test it -- --ignored ragdoll_drop::the_at_rest_drop_comes_to_rest_on_nearly_every_layout \
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

/// Issue 10's 1 cm as a rate over many landings: the `redetect_sweeps` variant, its stacking
/// ratio capped at e, keeps the deepest overlap of the landing (150 frames) within 1 cm on
/// nearly every layout and rarely explodes, and fails fewer layouts than the same variant
/// uncapped. Measured over layouts 1-64 x both spines: capped 0 over 1 cm and no explosion,
/// uncapped 2 (3.85 and 2.34 cm) and none; before the variant's exact joints and six sweeps
/// (stop 46: cheap joints, three sweeps) capped 0 and 1 (layout 52, rod), uncapped 7 and 4
/// (docs/solver.md, Landings that hold). A survey of 256 runs, so not run by default.
#[test]
#[ignore = "a survey of 256 landings (about 3 min on 2 cores): cargo test --release --test it \
            -- --ignored ragdoll_drop::the_capped_ratio_keeps_nearly_every_landing_within_a_centimetre \
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

/// The drop at one of its variants, spine and layout seed: the total dislocation (cm) per frame.
fn dislocation_per_frame(variant: Option<&str>, spine: SpineKind, seed: u64) -> Vec<f32> {
    let overrides = Overrides {
        spine: Some(spine),
        seed: Some(seed),
        ..Default::default()
    };
    let scene = load_scene(SCENE.as_ref(), variant, &overrides).unwrap();
    let mut lab = scene.build().unwrap();
    let report = sim::run(&mut lab, scene.def.frames, &mut sim::NoObserver).unwrap();
    report.total_dislocation_cm
}

/// Stacking carries the pile's weight (issue 10, the settled residual): the scene's `stacked`
/// variant is the paper's method (one step of 20 iterations, cheap joints, hard contacts) with
/// PBD's mass scaling by height in the contacts, k = 10 /m. On the scene's layout it leaves
/// well under the paper's settled dislocation (frames 300-600) for both spines. Measured (seed
/// 7, total over 30 ragdolls, since the box's nearest point is exact): chain3 54.8 -> 25.1 cm,
/// rod 43.5 -> 20.9 cm (docs/solver.md, Stacking, for other layouts).
#[test]
fn stacking_leaves_less_than_two_thirds_of_the_papers_settled_dislocation() {
    let _alone = one_at_a_time();
    for spine in [SpineKind::Chain3, SpineKind::Rod] {
        let paper = mean(&dislocation_per_frame(None, spine, 7)[300..]);
        let stacked = mean(&dislocation_per_frame(Some("stacked"), spine, 7)[300..]);
        println!(
            "{spine}: settled total dislocation {paper:.1} cm (paper) -> {stacked:.1} cm (stacked)"
        );
        assert!(
            stacked < 0.66 * paper,
            "{spine}: stacking left {stacked} cm against the paper's {paper} cm"
        );
    }
}

/// The paper's result with contacts that hold (issue 10's target: the rod below chain3 on at
/// least 90% of all frames, over the scene's layout and seeds 1-3). At the `stacked` variant
/// (the paper's 1 x 20 with stacking) the rod is lower on 534 / 573 / 572 / 568 of the 600
/// frames of layouts 7 / 1 / 2 / 3 (2247 of 2400, 93.6%) and on every settled frame (300-600),
/// where the paper's plain method, the reference, gives 88.3% (the test above) and the
/// `at_rest` variant, whose piles fall asleep wherever they stop, 78.0%.
#[test]
fn with_stacking_the_rod_spine_is_lower_on_nine_frames_in_ten() {
    let _alone = one_at_a_time();
    let (mut lower, mut frames, mut settled_lower, mut settled) = (0, 0, 0, 0);
    for seed in [7, 1, 2, 3] {
        let chain3 = dislocation_per_frame(Some("stacked"), SpineKind::Chain3, seed);
        let rod = dislocation_per_frame(Some("stacked"), SpineKind::Rod, seed);
        let below = |from: usize| {
            (chain3[from..].iter().zip(&rod[from..]))
                .filter(|(c, r)| r < c)
                .count()
        };
        println!(
            "seed {seed}: rod below chain3 on {} of {} frames",
            below(0),
            rod.len()
        );
        (lower, frames) = (lower + below(0), frames + rod.len());
        (settled_lower, settled) = (settled_lower + below(300), settled + rod.len() - 300);
    }
    assert!(
        lower as f32 >= 0.9 * frames as f32,
        "stacked: rod below chain3 on only {lower} of {frames} frames"
    );
    assert!(
        settled_lower as f32 >= 0.97 * settled as f32,
        "stacked: rod below chain3 on only {settled_lower} of {settled} settled frames"
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
    let scene = load_scene(SCENE.as_ref(), Some("redetect_sweeps"), &overrides).unwrap();
    let mut lab = scene.build().unwrap();
    let mut per_frame = Vec::new();
    let mut observer =
        |_: &Lab, m: &rodlab::metrics::FrameMetrics| per_frame.push(m.max_overlap_cm);
    let report = sim::run(&mut lab, 150, &mut observer).unwrap();
    (mean(&per_frame), report.max_overlap_cm)
}

/// Issue 10's 1 cm: the contacts solved alone after each substep's joint sweep push out what
/// that sweep left, so the landing stays within a centimetre for both spines (over the whole
/// 10 s and layouts 7 / 1 / 2 / 3 the deepest is 0.05-0.13 cm, `rodlab layouts
/// scenes/ragdoll_drop.toml --variant redetect_sweeps --seeds 1-3,7`); here 0.06 / 0.13 cm
/// (chain3 / rod) where the same method without them lets 0.63 / 1.76 cm through; and each
/// frame's deepest overlap is smaller on average (0.006 against 0.07 cm).
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
/// `redetect_sweeps` (the paper's cheap joints, three contact sweeps; printed, not asserted, as
/// one pile is a chaotic sample), layout 52's rod pile threw a forearm pressed between
/// two other ragdolls past 500 rad/s at frame 82, the one-row hinge turning it about its own
/// axis back and forth every substep. At the variant (exact joints, whose hinge aligns its
/// axes as one block, and six sweeps) the same landing runs its 150 frames within 1 cm
/// (measured 0.07 cm).
#[test]
fn the_landing_whose_forearm_exploded_with_cheap_joints_holds_with_exact_ones() {
    let _alone = one_at_a_time();
    let landing = |joint_flavour: Option<JointFlavour>, contact_extra_sweeps: Option<u32>| {
        let overrides = Overrides {
            spine: Some(SpineKind::Rod),
            seed: Some(52),
            frames: Some(150),
            joint_flavour,
            contact_extra_sweeps,
            ..Default::default()
        };
        let scene = load_scene(SCENE.as_ref(), Some("redetect_sweeps"), &overrides).unwrap();
        let mut lab = scene.build().unwrap();
        sim::run(&mut lab, 150, &mut sim::NoObserver).map(|r| r.max_overlap_cm)
    };
    // stop 46's variant: cheap joints, three sweeps (an explosion, printed, not asserted: one
    // pile is a chaotic sample)
    let cheap = landing(Some(JointFlavour::Cheap), Some(3));
    println!("with cheap joints and three sweeps: {cheap:?}");
    let deepest = landing(None, None).expect("no explosion with the variant's exact joints");
    println!("with the variant's exact joints: deepest overlap {deepest:.2} cm");
    assert!(deepest <= 1.0, "{deepest} cm");
}
