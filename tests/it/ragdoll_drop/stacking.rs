//! Stacking carries the pile's weight (issue 10, the settled residual and the paper's result
//! at 90%).

use super::*;
use rodlab::sim;

/// The drop at one of its variants, spine and layout seed: the total dislocation (cm) per frame.
fn dislocation_per_frame(variant: Option<&str>, spine: SpineKind, seed: u64) -> Vec<f32> {
    let (scene, mut lab) = drop_lab(variant, &spine_and_seed(spine, seed));
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
/// where the paper's plain method, the reference, gives 88.3% (`paper.rs`) and the
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
