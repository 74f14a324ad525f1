//! The paper's drop result at its own method (one step of 20 iterations, cheap joints, hard
//! contacts): the reference line.

use super::*;
use rodlab::sim;

/// Runs the drop with one spine and layout seed; returns the final lab, the total dislocation
/// (cm) per frame and the lowest body centre (m).
fn drop(spine: SpineKind, seed: u64) -> (Lab, Vec<f32>, f32) {
    let (scene, mut lab) = drop_lab(None, &spine_and_seed(spine, seed));
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
    // bound stays at 80% here; the 90% is held at the stacked variant (`stacking.rs`).
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
