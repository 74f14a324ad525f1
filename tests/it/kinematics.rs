//! Fig. 6: a chain whose joints bend equally reaches nearly where the rod does; a chain whose
//! joints bend unequally does not; and the equal chain converges to the rod as joints are added.

use rodlab::constraint::rod::chord_ratio;
use rodlab::kinematics::{chain_points, equal_weights, max_end_gap, rod_points, Comparison};

const LENGTH: f32 = 0.385;
const MAX_BEND: f32 = 150.0 * std::f32::consts::PI / 180.0;

#[test]
fn equal_chain_follows_the_rod_and_unequal_does_not() {
    let equal = max_end_gap(LENGTH, &equal_weights(3), MAX_BEND, 121);
    let unequal = max_end_gap(LENGTH, &[0.6, 0.3, 0.1], MAX_BEND, 121);
    // 1.8 cm at a 150 degree bend: under 5% of the length
    assert!(equal < 0.05 * LENGTH, "equal-angle chain strays {equal} m");
    assert!(
        unequal > 5.0 * equal,
        "unequal {unequal} m vs equal {equal} m"
    );
}

#[test]
fn equal_chain_converges_to_the_rod() {
    let gaps: Vec<f32> = [2, 4, 8, 16]
        .iter()
        .map(|&n| max_end_gap(LENGTH, &equal_weights(n), MAX_BEND, 61))
        .collect();
    for pair in gaps.windows(2) {
        // second-order: doubling the joints cuts the gap about fourfold
        assert!(pair[1] < 0.35 * pair[0], "gaps {gaps:?}");
    }
}

#[test]
fn rod_end_obeys_the_chord_formula() {
    for psi in [0.0f32, 0.3, 1.0, 2.0, 3.0] {
        let end = *rod_points(LENGTH, psi, 9).last().unwrap();
        let expected = LENGTH * chord_ratio(psi);
        assert!(
            (end.length() - expected).abs() < 1e-5,
            "psi {psi}: |end| {} vs {expected}",
            end.length()
        );
        // the chord leaves at half the bend angle (the tangents are reflections about it)
        let chord_angle = end.z.atan2(end.y);
        assert!(
            (chord_angle.abs() - psi / 2.0).abs() < 1e-4,
            "psi {psi}: chord angle {chord_angle}"
        );
    }
    // chains keep their length whatever the bend
    let points = chain_points(LENGTH, 1.2, &[0.5, 0.2, 0.3]);
    let length: f32 = points.windows(2).map(|w| (w[1] - w[0]).length()).sum();
    assert!((length - LENGTH).abs() < 1e-5);
}

/// The comparison the recording draws and the summary prints gives the gaps `max_end_gap`
/// measures on its own (the unequal shares normalised, the rod sampled finely).
#[test]
fn the_recorded_comparison_gives_the_measured_gaps() {
    let comparison = Comparison::new(LENGTH, 3, &[6.0, 3.0, 1.0], MAX_BEND, 121);
    let (equal, unequal) = comparison.largest_gaps();
    let expected_equal = max_end_gap(LENGTH, &equal_weights(3), MAX_BEND, 121);
    let expected_unequal = max_end_gap(LENGTH, &[0.6, 0.3, 0.1], MAX_BEND, 121);
    assert!(
        (equal - expected_equal).abs() < 1e-5,
        "{equal} vs {expected_equal}"
    );
    assert!(
        (unequal - expected_unequal).abs() < 1e-5,
        "{unequal} vs {expected_unequal}"
    );
    assert_eq!(comparison.bends.len(), 121);
    assert_eq!(comparison.bends[60], 0.0, "the middle bend is straight");
}
