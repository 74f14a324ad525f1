//! Stacking carries the pile's weight: the scene's `stacked` variant is the paper's method (one
//! step of 20 iterations, cheap joints, hard contacts) with PBD's mass scaling by height in the
//! contacts (k = 10 /m), as rates over layouts 1-16 x both spines against the paper's own runs
//! (`paper.rs`).

use super::paper::{ends, layouts, LAYOUTS};
use super::*;

/// The settled residual (the total dislocation over frames 300-600): with stacking it is under
/// two thirds of the paper's on the mean over the layouts, for both spines, and lower than the
/// paper's on at least 14 of the 16 layouts.
#[test]
fn stacking_leaves_less_than_two_thirds_of_the_papers_settled_dislocation() {
    let (paper, stacked) = (layouts(None), layouts(Some("stacked")));
    for spine in [SpineKind::Chain3, SpineKind::Rod] {
        let [paper, stacked] = [paper, stacked].map(|runs| {
            let ends = ends(runs, spine);
            ends.iter()
                .map(|e| e.settled_dislocation_cm)
                .collect::<Vec<f32>>()
        });
        let lower = paper.iter().zip(&stacked).filter(|(p, s)| s < p).count();
        let (paper_mean, stacked_mean) = (mean(&paper), mean(&stacked));
        println!(
            "{spine}: settled total dislocation, mean over layouts {LAYOUTS:?}: paper \
             {paper_mean:.1} cm, stacked {stacked_mean:.1} cm ({:.2}x); lower on {lower} of {} \
             layouts",
            stacked_mean / paper_mean,
            paper.len()
        );
        assert!(
            stacked_mean < 0.66 * paper_mean,
            "{spine}: stacking left {stacked_mean} cm against the paper's {paper_mean} cm"
        );
        assert!(
            lower >= 14,
            "{spine}: stacking lower on only {lower} layouts"
        );
    }
}

/// The paper's result with contacts that hold: at the `stacked` variant the rod's settled
/// residual is below chain3's on at least 15 of the 16 layouts, and on their mean by more than
/// at the paper's plain method, the reference.
#[test]
fn with_stacking_the_rod_spine_is_lower_on_nearly_every_layout() {
    let (paper, stacked) = (layouts(None), layouts(Some("stacked")));
    let settled = |runs, spine| -> Vec<f32> {
        let ends = ends(runs, spine);
        ends.iter().map(|e| e.settled_dislocation_cm).collect()
    };
    let lower = |runs| {
        let (chain3, rod) = (
            settled(runs, SpineKind::Chain3),
            settled(runs, SpineKind::Rod),
        );
        let below = chain3.iter().zip(&rod).filter(|(c, r)| r < c).count();
        (below, mean(&rod) / mean(&chain3))
    };
    let (stacked_below, stacked_ratio) = lower(stacked);
    let (paper_below, paper_ratio) = lower(paper);
    println!(
        "settled: rod below chain3 on {stacked_below} of 16 layouts stacked ({stacked_ratio:.2}x \
         chain3's mean), {paper_below} at the paper's method ({paper_ratio:.2}x)"
    );
    assert!(
        stacked_below >= 15,
        "stacked: rod lower on only {stacked_below} of 16"
    );
    assert!(
        stacked_ratio < paper_ratio,
        "{stacked_ratio} against the paper's {paper_ratio}"
    );
}
