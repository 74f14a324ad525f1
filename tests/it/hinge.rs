//! A hinge limit (elbow, knee: `swing_max = 0`) holds the two joint frames' x axes aligned,
//! two rows across a's axis. One row along the error is exact only where the pair's inertia is
//! isotropic about it; a limb's axial inverse inertia is tens of times its transverse one, so
//! the row mostly spins the limb about its long axis and leaves an error across the first. In
//! the drop's settled piles that row's leftovers, sandwiched between contacts, became a twist
//! back and forth across an elbow every substep (8 rad/s at the frame's end while the limbs
//! stayed put), which kept 7 of 26 piles awake past 10 s. The exact flavour solves the two rows
//! as one 2x2 block (`relative_rotation_across`); the cheap flavour keeps the one row.

use rodlab::body::{Body, BodyKind};
use rodlab::constraint::parts::relative_rotation_across;
use rodlab::constraint::AngularLimit;
use rodlab::math::{angle_between, Quat, Vec3};
use rodlab::shape::{Axis, Shape};
use rodlab::solver::body::SolverBody;

/// An upper arm and a forearm along -y, hinged about x at the elbow, the forearm turned by
/// `error` rad about an axis across x halfway between its long axis and z; both movable, or the
/// upper arm fixed.
fn arm(error: f32, upper_fixed: bool) -> (SolverBody, SolverBody) {
    let limb = |name: &str, kind, half_height: f32, radius: f32, mass: f32, y: f32| {
        let shape = Shape::Capsule {
            half_height,
            radius,
            axis: Axis::Y,
        };
        Body::new(name, kind, shape, mass).with_pose(Vec3::new(0.0, y, 0.0), Quat::IDENTITY)
    };
    let upper_kind = match upper_fixed {
        true => BodyKind::Fixed,
        false => BodyKind::Dynamic,
    };
    let upper = limb("upper_arm", upper_kind, 0.1, 0.05, 2.0, 1.2);
    let mut fore = limb("forearm", BodyKind::Dynamic, 0.09, 0.04, 1.4, 0.9);
    let across = Vec3::new(0.0, 1.0, 1.0).normalize();
    fore.set_pose(fore.position, Quat::from_axis_angle(across, error));
    (SolverBody::from_body(&upper), SolverBody::from_body(&fore))
}

/// Angle between the two bodies' x axes (the hinge's error), after one projection of the hinge
/// by the block or by one row.
fn swing_after_one_projection(error: f32, upper_fixed: bool, block: bool) -> f32 {
    let (mut a, mut b) = arm(error, upper_fixed);
    let hinge = AngularLimit::hinge(-1.0, 2.5);
    hinge.solve(&mut a, &mut b, Quat::IDENTITY, Quat::IDENTITY, 0.0, block);
    angle_between(a.orientation * Vec3::X, b.orientation * Vec3::X)
}

/// The block removes the error to second order in one projection; one row leaves a large part
/// of it (the inertia turned it into axial spin), with the upper arm free or fixed.
#[test]
fn the_exact_hinge_aligns_a_limbs_axes_in_one_projection_where_one_row_does_not() {
    for upper_fixed in [false, true] {
        for error in [0.01f32, 0.05, 0.2] {
            let block = swing_after_one_projection(error, upper_fixed, true);
            let row = swing_after_one_projection(error, upper_fixed, false);
            println!("error {error}, upper fixed {upper_fixed}: block leaves {block:.2e} rad, one row {row:.2e}");
            assert!(
                block < 0.5 * error * error,
                "block left {block} of {error} rad (upper fixed {upper_fixed})"
            );
            assert!(
                row > 0.2 * error,
                "one row left only {row} of {error} rad: the block's case for itself is gone"
            );
        }
    }
}

/// The block is an internal angular impulse: the pair's angular momentum about its centre of
/// mass (here: the turn weighted by inertia) is unchanged, and the turn about the hinge axis,
/// which the hinge allows, is what the inertia couples in; and with nothing to correct it does
/// nothing.
#[test]
fn the_hinge_block_is_an_equal_and_opposite_angular_impulse() {
    let (mut a, mut b) = arm(0.05, false);
    let (a0, b0) = (a, b);
    let ax = a.orientation * Vec3::X;
    let error =
        -angle_between(ax, b.orientation * Vec3::X) * ax.cross(b.orientation * Vec3::X).normalize();
    relative_rotation_across(&mut a, &mut b, error, ax);
    // I dtheta summed over the pair: the impulses -L and L cancel
    let inertia = |s: &SolverBody| s.inverse_inertia.inverse();
    let momentum = inertia(&a) * a.rotation_correction + inertia(&b) * b.rotation_correction;
    let scale = (inertia(&b) * b.rotation_correction).length();
    assert!(
        momentum.length() < 1e-4 * scale,
        "net angular impulse {momentum} against {scale}"
    );
    // the relative turn across the axis is the error
    let relative = b.rotation_correction - a.rotation_correction;
    let across = relative - relative.dot(ax) * ax;
    assert!(
        (across - error).length() < 1e-5,
        "turned {across} across the axis, asked {error}"
    );
    // no error, no turn
    let (mut a, mut b) = (a0, b0);
    relative_rotation_across(&mut a, &mut b, Vec3::ZERO, ax);
    assert_eq!(
        (a.orientation, b.orientation),
        (a0.orientation, b0.orientation)
    );
}
