//! The broad phase's gap bounds (`contact::broadphase::gaps`): a pair whose shapes are proven
//! out of reach skips the narrow phase, and that must never lose a contact point. Each frame of
//! the drop (30 ragdolls falling onto stairs, a ramp and crates, then settling) and of a
//! thrown crowd is detected afresh, with no bounds, and compared with the points the world's
//! own detection, which carries its bounds from frame to frame, found at the same poses.

use crate::common::lab_with;
use rodlab::contact::{ContactPoint, Contacts};
use rodlab::lab::Lab;
use rodlab::ragdoll::SpineKind;
use rodlab::sim::Overrides;

/// What the narrow phase decides about a point (its impulses and anchors come from history).
fn geometry(points: &[ContactPoint]) -> Vec<(u32, u32, u32, [u32; 9])> {
    let bits = |v: rodlab::math::Vec3| v.to_array().map(f32::to_bits);
    let mut keys: Vec<_> = (points.iter())
        .map(|p| {
            let [n, a, b] = [bits(p.normal), bits(p.local_a), bits(p.local_b)];
            let all = [n[0], n[1], n[2], a[0], a[1], a[2], b[0], b[1], b[2]];
            (p.body_a.0, p.body_b.0, p.id, all)
        })
        .collect();
    keys.sort_unstable();
    keys
}

/// Steps `lab` for `frames`, checking every frame's points against a fresh detection; returns
/// the pairs skipped and the points found, summed over the frames.
fn compare(lab: &mut Lab, frames: u32) -> (usize, usize) {
    let (mut skipped, mut found) = (0, 0);
    for frame in 0..frames {
        let world = &lab.world;
        let (dt, margin) = (world.settings.dt, world.settings.contact_margin);
        let mut fresh = Contacts::default();
        fresh.detect(&world.bodies, &world.constraints, dt, margin);
        lab.step().unwrap();
        let kept = &lab.world.contacts;
        assert_eq!(
            geometry(&kept.points),
            geometry(&fresh.points),
            "frame {frame}: the points differ from a detection without bounds"
        );
        skipped += kept.pairs_skipped();
        found += kept.points.len();
    }
    (skipped, found)
}

#[test]
fn bounds_skip_only_pairs_that_make_no_point_in_the_drop() {
    for spine in [SpineKind::Rod, SpineKind::Chain3] {
        let overrides = Overrides {
            spine: Some(spine),
            ..Default::default()
        };
        let (mut lab, _) = lab_with("ragdoll_drop", overrides);
        let (skipped, found) = compare(&mut lab, 240);
        println!("{spine}: {skipped} pairs skipped and {found} points found over 240 frames");
        // the bounds must be doing something for this test to mean anything
        assert!(
            skipped > found / 10,
            "{spine}: only {skipped} pairs skipped"
        );
    }
}

/// Limbs thrown at 8 m/s and spun at 20 rad/s move centimetres a frame: the bounds fall fast,
/// and a pair must be tested again before its shapes can meet.
#[test]
fn bounds_skip_only_pairs_that_make_no_point_when_bodies_are_thrown() {
    let overrides = Overrides {
        spine: Some(SpineKind::Rod),
        ..Default::default()
    };
    let (mut lab, _) = lab_with("ragdoll_drop", overrides);
    for (i, body) in lab.world.bodies.iter_mut().enumerate() {
        if body.is_dynamic() {
            let k = i as f32;
            body.linear_velocity =
                rodlab::math::Vec3::new(8.0 * (k * 0.7).sin(), 2.0, 8.0 * (k * 1.3).cos());
            body.angular_velocity = rodlab::math::Vec3::new(20.0 * (k * 0.3).cos(), 10.0, 0.0);
        }
    }
    let (skipped, found) = compare(&mut lab, 90);
    println!("thrown: {skipped} pairs skipped and {found} points found over 90 frames");
    assert!(skipped > 0);
}
