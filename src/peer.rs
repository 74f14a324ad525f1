//! Rapier (`rapier3d` 0.36) as a peer engine on the speed/accuracy chart of [`crate::sweep`]:
//! the same scene, built from rodlab's own [`World`](crate::world::World) so both engines start
//! from the identical state, stepped by Rapier and measured by rodlab's
//! [`crate::metrics::FrameMetrics`] after every step.
//!
//! Mapped one to one:
//! - bodies: fixed, dynamic, kinematic (velocity based: it moves with its prescribed velocity,
//!   as in rodlab); pose, velocities, mass and principal inertia (body frame = principal frame;
//!   colliders have zero density so they add no mass), constant external forces (Rapier keeps
//!   a force once added), damping (same `v /= 1 + dt c` law), gravity, `dt`;
//! - shapes: sphere, capsule along its axis, cuboid, half-space with normal `+Y` in body space;
//!   collision filter bits, restitution (larger of the pair), contact margin as Rapier's
//!   prediction distance. With contacts off no collider is created, so Rapier does no
//!   collision work either;
//! - ball-and-socket joints: a generic joint with locked linear axes at the same local anchors
//!   and local frames (x = twist axis); bodies joined by one collide only if `collide_connected`;
//!   twist limit on the frame's x axis (the same angle: `2 atan2(q_x, q_w)` of `F_a^-1 F_b`); a
//!   hinge locks the other two axes; a swing cone is Rapier's coupled y-z limit, a true cone on
//!   the angle between the two x axes;
//! - a hard angular target (spring relaxation 1) locks all three angular axes at the rest pose;
//! - contact filters (`Constraints::filter_contacts`, a ragdoll's `self_contacts`): a contact
//!   pair filter hook over those colliders, which refuses the filtered pairs (and the jointed
//!   ones) and otherwise keeps Rapier's default (no contacts between two non-dynamic bodies).
//!
//! Approximated:
//! - friction: Rapier has one coefficient; we use rodlab's dynamic one, combined as the
//!   geometric mean like rodlab's;
//! - a soft spring (relaxation `a` < 1) becomes position motors on the three angular axes toward
//!   the rest relative rotation. Its stiffness (acceleration based, no damping) is chosen so one
//!   implicit step of the spring alone removes the same fraction `1 - (1 - a)^N` of the error as
//!   rodlab's `N` relaxations do, with `N` the iteration count of the run. Rapier ignores motors
//!   on coupled axes, so a joint with a soft spring limits its swing with a box, `[-swing,
//!   swing]` on the y and z axes, instead of the cone;
//! - the iteration knob is `IntegrationParameters::num_solver_iterations`, which in Rapier 0.36
//!   is a number of substeps (TGS soft, one PGS iteration each), not of Gauss-Seidel sweeps;
//! - sleeping is off (the paper's scenes run rodlab without it, and a sleeping pile would cost
//!   Rapier nothing); Rapier's other defaults (speed caps, joint softness, contact softness, warm starting) stay on.
//!
//! Not mapped: rod constraints (the paper's rod has no Rapier counterpart), so a scene with a
//! rod spine is refused.
//!
//! Seen with these defaults: a chain3 spine without springs, slumped onto its swing limits,
//! creeps past the middle joint's limit (to 1.6 rad against 0.44 in passive bending, even at
//! 32 iterations), because a limit row's correction is capped at `max_corrective_velocity`
//! (3 rad/s) and one PGS pass per substep does not hold the chain; more PGS passes
//! (`num_internal_pgs_iterations = 4`) or no cap keep it within 0.01 rad.

use std::time::Instant;

use anyhow::bail;
use rapier3d::math::{Pose, Rotation, Vector};
use rapier3d::prelude::{
    ActiveHooks, CoefficientCombineRule, ColliderBuilder, ColliderHandle, GenericJoint, Group,
    InteractionGroups, InteractionTestMode, JointAxesMask, JointAxis, MassProperties,
    PairFilterContext, PhysicsHooks, PhysicsWorld, RigidBody, RigidBodyBuilder, RigidBodyHandle,
    SharedShape, SolverFlags,
};
use std::collections::HashSet;

use crate::body::{Body, BodyKind};
use crate::constraint::{BallSocket, Constraint};
use crate::lab::Lab;
use crate::math::{Quat, Vec3};
use crate::ragdoll::SpineKind;
use crate::scene::Scene;
use crate::shape::{Axis, Shape};
use crate::sweep::SweepRow;
use crate::world::{Settings, World};

/// A rodlab world rebuilt in Rapier; body `i` of the world is `handles[i]`.
pub struct RapierWorld {
    /// Rapier's bodies, colliders, joints and pipeline.
    pub physics: PhysicsWorld,
    handles: Vec<RigidBodyHandle>,
    /// The world's contact filters, as a hook (None: the world filters no pairs).
    filters: Option<ContactFilters>,
}

/// The collider pairs never to collide, for Rapier's contact pair filter hook.
struct ContactFilters(HashSet<(u32, u32)>);

impl ContactFilters {
    fn key(a: ColliderHandle, b: ColliderHandle) -> (u32, u32) {
        let (a, b) = (a.into_raw_parts().0, b.into_raw_parts().0);
        (a.min(b), a.max(b))
    }
}

impl PhysicsHooks for ContactFilters {
    fn filter_contact_pair(&self, pair: &PairFilterContext) -> Option<SolverFlags> {
        if self.0.contains(&Self::key(pair.collider1, pair.collider2)) {
            return None;
        }
        // a hook replaces Rapier's default filter: no contacts between two non-dynamic bodies
        let dynamic = |c: ColliderHandle| {
            (pair.colliders[c].parent()).is_some_and(|b| pair.bodies[b].is_dynamic())
        };
        (dynamic(pair.collider1) || dynamic(pair.collider2))
            .then_some(SolverFlags::COMPUTE_RIGID_IMPULSES)
    }
}

impl RapierWorld {
    /// Rebuilds `world` (at its current state) in Rapier, with `iterations` solver iterations.
    pub fn new(world: &World, iterations: u32) -> anyhow::Result<Self> {
        let s = &world.settings;
        let mut physics = PhysicsWorld::new();
        physics.gravity = to_rapier(s.gravity);
        let params = &mut physics.integration_parameters;
        params.dt = s.dt;
        params.num_solver_iterations = iterations.max(1) as usize;
        params.normalized_prediction_distance = s.contact_margin;
        let filtered = world.constraints.contact_filters();
        let mut hooked = vec![false; world.bodies.len()];
        for &(a, b) in filtered {
            (hooked[a.index()], hooked[b.index()]) = (true, true);
        }
        let mut handles = Vec::with_capacity(world.bodies.len());
        let mut colliders = Vec::with_capacity(world.bodies.len());
        for (b, &hooked) in world.bodies.iter().zip(&hooked) {
            let handle = physics.bodies.insert(rigid_body(b, s));
            physics.bodies[handle].add_force(to_rapier(b.external_force), false);
            if s.contacts {
                let mut builder = collider(b);
                if hooked {
                    builder = builder.active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
                }
                let collider =
                    physics
                        .colliders
                        .insert_with_parent(builder, handle, &mut physics.bodies);
                colliders.push(Some(collider));
            } else {
                colliders.push(None);
            }
            handles.push(handle);
        }
        for c in &world.constraints {
            let Constraint::BallSocket(j) = c else {
                bail!(
                    "constraint \"{}\" is a rod: rods have no Rapier counterpart (use spine chain3 or single)",
                    c.name()
                );
            };
            let (a, b) = (handles[j.body_a.index()], handles[j.body_b.index()]);
            physics
                .impulse_joints
                .insert(a, b, joint(j, iterations, s.dt), true);
        }
        // the filtered pairs, and the jointed ones (which the hook must refuse too, as it
        // replaces the filtering of the pairs it is asked about)
        let keys = world.constraints.pairs_kept_apart().filter_map(|(a, b)| {
            let (a, b) = (colliders[a.index()]?, colliders[b.index()]?);
            Some(ContactFilters::key(a, b))
        });
        let filters = (!filtered.is_empty() && s.contacts).then(|| ContactFilters(keys.collect()));
        Ok(RapierWorld {
            physics,
            handles,
            filters,
        })
    }

    /// One Rapier step (`PhysicsPipeline::step`, no events; the contact filter hook where the
    /// world filters pairs).
    pub fn step(&mut self) {
        match &self.filters {
            Some(filters) => self.physics.step_with_events(filters, &()),
            None => self.physics.step(),
        }
    }

    /// Copies Rapier's poses and velocities into `world` (current and preview pose, which the
    /// residual measures read) and advances its frame counter and clock.
    pub fn write_back(&self, world: &mut World) {
        for (body, &handle) in world.bodies.iter_mut().zip(&self.handles) {
            let rb = &self.physics.bodies[handle];
            let pose = rb.position();
            body.set_pose(
                from_rapier(pose.translation),
                from_rapier_quat(pose.rotation),
            );
            body.linear_velocity = from_rapier(rb.linvel());
            body.angular_velocity = from_rapier(rb.angvel());
        }
        world.frame += 1;
        world.time += world.settings.dt as f64;
    }
}

/// The Rapier build this binary carries, as its chart line names it.
pub const BUILD: &str = match (
    cfg!(feature = "rapier-simd8"),
    cfg!(feature = "rapier-parallel"),
) {
    (false, false) => "rapier",
    (true, false) => "rapier simd8",
    (false, true) => "rapier parallel",
    (true, true) => "rapier simd8 parallel",
};

/// Runs `scene` (overrides already applied to `scene.def`; spine chain3 or single) in Rapier
/// with `iterations` solver iterations, `repeats` times, measured like [`crate::sweep::run_one`]:
/// `step_us` is the median wall time of the Rapier step alone after the same warm-up, pooled
/// over repeats; the residuals are rodlab's measures of the first repeat.
pub fn run(scene: &Scene, iterations: u32, repeats: u32) -> anyhow::Result<SweepRow> {
    let def = &scene.def;
    if let Some(r) = def.ragdoll.iter().find(|r| r.spine == SpineKind::Rod) {
        bail!(
            "ragdoll \"{}\" has a rod spine, which has no Rapier counterpart: run the Rapier peer with spine chain3 or single",
            r.name
        );
    }
    let mut spines: Vec<String> = def.ragdoll.iter().map(|r| r.spine.to_string()).collect();
    spines.sort();
    spines.dedup();
    let spine = if spines.is_empty() {
        "none".to_string()
    } else {
        spines.join("+")
    };
    let row = SweepRow::new(
        BUILD.into(),
        spine,
        "spherical".into(),
        crate::world::Settings {
            dt: def.dt,
            iterations,
            ..Default::default()
        },
    );
    crate::sweep::time_and_measure(row, def.frames, repeats, || {
        let lab = scene.build()?;
        let peer = RapierWorld::new(&lab.world, iterations)?;
        Ok(PeerRun { lab, peer })
    })
}

/// A Rapier world and the rodlab lab its poses are copied into for measuring.
struct PeerRun {
    lab: Lab,
    peer: RapierWorld,
}

impl crate::sweep::Timed for PeerRun {
    fn step_timed(&mut self) -> Result<f64, String> {
        let start = Instant::now();
        self.peer.step();
        let elapsed = start.elapsed().as_secs_f64() * 1e6;
        self.peer.write_back(&mut self.lab.world);
        self.lab
            .world
            .check_health()
            .map(|()| elapsed)
            .map_err(|e| e.to_string())
    }

    fn measured(&self) -> &Lab {
        &self.lab
    }
}

fn rigid_body(b: &Body, s: &Settings) -> RigidBody {
    let builder = match b.kind {
        BodyKind::Fixed => RigidBodyBuilder::fixed(),
        BodyKind::Kinematic => RigidBodyBuilder::kinematic_velocity_based(),
        BodyKind::Dynamic => RigidBodyBuilder::dynamic()
            .additional_mass_properties(MassProperties::new(
                Vector::ZERO,
                b.mass,
                to_rapier(b.inertia),
            ))
            .linear_damping(s.linear_damping)
            .angular_damping(s.angular_damping),
    };
    builder
        .pose(Pose::from_parts(
            to_rapier(b.position),
            to_rapier_quat(b.orientation),
        ))
        .linvel(to_rapier(b.linear_velocity))
        .angvel(to_rapier(b.angular_velocity))
        .can_sleep(false)
        .build()
}

fn collider(b: &Body) -> ColliderBuilder {
    let builder = match b.shape {
        Shape::Sphere { radius } => ColliderBuilder::ball(radius),
        Shape::Capsule {
            half_height,
            radius,
            axis,
        } => match axis {
            Axis::X => ColliderBuilder::capsule_x(half_height, radius),
            Axis::Y => ColliderBuilder::capsule_y(half_height, radius),
            Axis::Z => ColliderBuilder::capsule_z(half_height, radius),
        },
        Shape::Cuboid { half_extents: h } => ColliderBuilder::cuboid(h.x, h.y, h.z),
        Shape::HalfSpace => ColliderBuilder::new(SharedShape::halfspace(Vector::Y)),
    };
    builder
        .density(0.0)
        .friction(b.dynamic_friction)
        .friction_combine_rule(CoefficientCombineRule::GeometricMean)
        .restitution(b.restitution)
        .restitution_combine_rule(CoefficientCombineRule::Max)
        .collision_groups(InteractionGroups::new(
            Group::from_bits_retain(b.collision_group),
            Group::from_bits_retain(b.collision_mask),
            InteractionTestMode::And,
        ))
}

/// The joint for a ball-and-socket (see the module docs for what is approximated).
fn joint(j: &BallSocket, iterations: u32, dt: f32) -> GenericJoint {
    use std::f32::consts::{PI, TAU};
    let mut joint = GenericJoint::new(JointAxesMask::LIN_AXES);
    joint.set_contacts_enabled(j.collide_connected);
    let frame = |anchor: Vec3, rotation: Quat| {
        Pose::from_parts(to_rapier(anchor), to_rapier_quat(rotation))
    };
    joint.set_local_frame1(frame(j.local_anchor_a, j.local_frame_a));
    joint.set_local_frame2(frame(j.local_anchor_b, j.local_frame_b));
    let spring = j.spring.filter(|s| s.relaxation > 0.0);
    if let Some(rest) = spring.filter(|s| s.relaxation >= 1.0).map(|s| s.rest) {
        // Hard target: frames that coincide at the rest pose, all angular axes locked.
        joint.set_local_frame2(frame(j.local_anchor_b, rest.inverse() * j.local_frame_a));
        joint.locked_axes |= JointAxesMask::ANG_AXES;
        return joint;
    }
    if let Some(limit) = j.limit {
        if limit.twist_max - limit.twist_min < TAU {
            joint.set_limits(JointAxis::AngX, [limit.twist_min, limit.twist_max]);
        }
        let swing = [-limit.swing_max, limit.swing_max];
        if limit.swing_max <= 0.0 {
            joint.locked_axes |= JointAxesMask::ANG_Y | JointAxesMask::ANG_Z; // hinge
        } else if limit.swing_max < PI && spring.is_some() {
            // Box: Rapier's motors ignore coupled axes.
            joint.set_limits(JointAxis::AngY, swing);
            joint.set_limits(JointAxis::AngZ, swing);
        } else if limit.swing_max < PI {
            // Cone: the coupled y-z limit bounds the angle between the two x axes.
            joint.set_limits(JointAxis::AngY, swing);
            joint.coupled_axes = JointAxesMask::ANG_Y | JointAxesMask::ANG_Z;
        }
    }
    if let Some(spring) = spring {
        // The rest relative rotation of the joint frames; Rapier's motor angle on axis i is
        // 2 asin(q_i) of the relative rotation (w >= 0), so these targets meet at the rest pose.
        let mut rest = j.local_frame_a.inverse() * spring.rest * j.local_frame_b;
        if rest.w < 0.0 {
            rest = -rest;
        }
        let removed = 1.0 - (1.0 - spring.relaxation as f64).powi(iterations.max(1) as i32);
        let stiffness = (removed / (1.0 - removed) / (dt as f64 * dt as f64)).min(1e12) as f32;
        for (axis, mask, q) in [
            (JointAxis::AngX, JointAxesMask::ANG_X, rest.x),
            (JointAxis::AngY, JointAxesMask::ANG_Y, rest.y),
            (JointAxis::AngZ, JointAxesMask::ANG_Z, rest.z),
        ] {
            if !joint.locked_axes.contains(mask) {
                joint.set_motor_position(axis, 2.0 * q.asin(), stiffness, 0.0);
            }
        }
    }
    joint
}

fn to_rapier(v: Vec3) -> Vector {
    Vector::from_array(v.to_array())
}

fn to_rapier_quat(q: Quat) -> Rotation {
    Rotation::from_array(q.to_array())
}

fn from_rapier(v: Vector) -> Vec3 {
    Vec3::from_array(v.to_array())
}

fn from_rapier_quat(q: Rotation) -> Quat {
    Quat::from_array(q.to_array())
}
