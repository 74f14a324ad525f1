//! [`RodRow`], the rod as the solver stores it, and its per-iteration projection of bend
//! (eq. 11), twist (eq. 12-13), curve (eq. 6) and length (eq. 9), with the compliant parts
//! ([`Compliant`], XPBD) and their velocity damping.

use super::{
    chord_ratio_derivative, curve_projection, length_error, measure_twist, offset_axis, BendTwist,
    LengthCorrection, Stiffness, TwistMode,
};
use crate::body::Body;
use crate::constraint::parts::{relative_rotation, relative_rotation_block};
use crate::math::{angle_between, any_perpendicular, Mat3, Quat, Vec3};
use crate::solver_body::pair_mut;
use crate::solver_body::SolverBody;

/// A rod as the solver stores it (hot data: indices, no name).
#[derive(Clone, Copy, Debug)]
pub struct RodRow {
    /// Index of body a in the world's bodies.
    pub body_a: u32,
    /// Index of body b in the world's bodies.
    pub body_b: u32,
    /// Rod frame in body a (eq. 2): x is the tangent, y the normal.
    pub frame_a: Quat,
    /// Rod frame in body b (eq. 2): x is the tangent, y the normal.
    pub frame_b: Quat,
    /// Rest length l_0 (m).
    pub rest_length: f32,
    /// Bending relaxation alpha_b in [0, 1] (eq. 11).
    pub alpha_bend: f32,
    /// Twisting relaxation alpha_t in [0, 1] (eq. 12-13).
    pub alpha_twist: f32,
    /// Stiffness in compliance form, with its state in the substep (replaces the alpha).
    pub bend_compliant: Option<Compliant>,
    /// Twist stiffness in compliance form, with its state in the substep (replaces alpha_t).
    pub twist_compliant: Option<Compliant>,
    /// How tau is measured.
    pub twist_mode: TwistMode,
    /// How the length constraint (eq. 9) is corrected.
    pub length_correction: LengthCorrection,
    /// How bend and twist are projected.
    pub bend_twist: BendTwist,
}

/// A compliant part (bend or twist) as the solver keeps it through one substep (XPBD).
#[derive(Clone, Copy, Debug)]
pub struct Compliant {
    /// Stiffness (N m/rad) and damping (N m s/rad) of this part.
    pub stiffness: Stiffness,
    /// `alpha~ = 1 / (k h^2)`.
    compliance: f32,
    /// The multiplier accumulated this substep.
    lambda: f32,
}

impl Compliant {
    pub(super) fn new(stiffness: Stiffness) -> Self {
        Compliant {
            stiffness,
            compliance: 0.0,
            lambda: 0.0,
        }
    }

    fn begin_substep(&mut self, h: f32) {
        self.compliance = 1.0 / (self.stiffness.stiffness * h * h);
        self.lambda = 0.0;
    }

    /// One XPBD update for the angle `c` with the pair's inverse inertia `w` about its axis:
    /// the angular impulse on b (a takes its negative).
    fn impulse(&mut self, c: f32, w: f32) -> f32 {
        let delta = (-c - self.compliance * self.lambda) / (w + self.compliance);
        self.lambda += delta;
        delta
    }
}

impl RodRow {
    /// Per-substep constants of the compliant parts.
    pub fn begin_substep(&mut self, h: f32) {
        for part in [&mut self.bend_compliant, &mut self.twist_compliant]
            .into_iter()
            .flatten()
        {
            part.begin_substep(h);
        }
    }

    /// The compliant parts' damping, on the velocities after the substep's positions are
    /// solved (as Mueller et al. 2020 damp XPBD joints, so damping adds no bias where the
    /// iterations have not converged): the relative angular velocity `w_rel` about the bend
    /// axis (and about `t_b`) becomes `w_rel / (1 + c h w)`, the implicit step of the torque
    /// `-c w_rel`, shared by the bodies' inertia about the axis.
    pub fn damp_velocities(&self, bodies: &mut [Body], h: f32) {
        let damping = |part: Option<Compliant>| part.map_or(0.0, |p| p.stiffness.damping);
        let (bend, twist) = (damping(self.bend_compliant), damping(self.twist_compliant));
        if bend == 0.0 && twist == 0.0 {
            return;
        }
        let (a, b) = pair_mut(bodies, self.body_a as usize, self.body_b as usize);
        let mobility = |body: &Body| {
            if body.is_awake_dynamic() {
                body.inverse_inertia_world()
            } else {
                Mat3::ZERO
            }
        };
        let (inverse_a, inverse_b) = (mobility(a), mobility(b));
        let (fa, fb) = (a.orientation * self.frame_a, b.orientation * self.frame_b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let bend_axis = ta.cross(tb).try_normalize();
        for (c, axis) in [(bend, bend_axis), (twist, Some(tb))] {
            let Some(n) = axis.filter(|_| c > 0.0) else {
                continue;
            };
            let w = n.dot(inverse_a * n) + n.dot(inverse_b * n);
            let relative = (b.angular_velocity - a.angular_velocity).dot(n);
            let impulse = -c * h * relative / (1.0 + c * h * w) * n;
            a.angular_velocity -= inverse_a * impulse;
            b.angular_velocity += inverse_b * impulse;
        }
    }

    /// One projection of bend, twist, curve and length, sharing the geometry (§7).
    #[inline(always)]
    pub fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        let (fa, fb) = (a.orientation * self.frame_a, b.orientation * self.frame_b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        if !self.bend_and_twist_as_block(a, b, (fa, fb), (ta, tb)) {
            self.bend_then_twist(a, b, (ta, tb));
        }
        self.curve_and_length(a, b);
    }

    /// [`BendTwist::Block`] where both parts act (alphas above 0, psi above 1e-7): both from
    /// the frames `fa, fb` as one 2x2 block. Returns whether it did.
    #[inline(always)]
    fn bend_and_twist_as_block(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        (fa, fb): (Quat, Quat),
        (ta, tb): (Vec3, Vec3),
    ) -> bool {
        let soft = self.bend_compliant.is_none() && self.twist_compliant.is_none();
        if !(self.bend_twist == BendTwist::Block && soft) {
            return false;
        }
        let psi = angle_between(ta, tb);
        if !(self.alpha_bend > 0.0 && self.alpha_twist > 0.0 && psi > 1e-7) {
            return false;
        }
        let axis = ta
            .cross(tb)
            .try_normalize()
            .unwrap_or_else(|| any_perpendicular(ta));
        let tau = measure_twist(self.twist_mode, fa, fb);
        let errors = (-self.alpha_bend * psi, -self.alpha_twist * tau);
        relative_rotation_block(a, b, (axis, tb), errors);
        true
    }

    /// Bend, then twist measured on the frames the bend left ([`BendTwist::Sequential`]).
    #[inline(always)]
    fn bend_then_twist(&mut self, a: &mut SolverBody, b: &mut SolverBody, (ta, tb): (Vec3, Vec3)) {
        if self.bend_compliant.is_some() || self.alpha_bend > 0.0 {
            let psi = angle_between(ta, tb);
            if psi > 1e-7 {
                let axis = ta
                    .cross(tb)
                    .try_normalize()
                    .unwrap_or_else(|| any_perpendicular(ta));
                if let Some(part) = &mut self.bend_compliant {
                    // Compliant bend: the torque k psi about t_a x t_b.
                    let w = a.angular_inverse_mass(axis) + b.angular_inverse_mass(axis);
                    let impulse = part.impulse(psi, w) * axis;
                    a.apply_angular_impulse(-impulse);
                    b.apply_angular_impulse(impulse);
                } else {
                    // Soft bend (eq. 11): remove alpha_b of psi about t_a x t_b.
                    relative_rotation(a, b, -self.alpha_bend * psi * axis);
                }
            }
        }
        if let Some(part) = &mut self.twist_compliant {
            // Compliant twist: the torque k tau about t_b.
            let (fa, fb) = (a.orientation * self.frame_a, b.orientation * self.frame_b);
            let tau = measure_twist(self.twist_mode, fa, fb);
            let axis = fb * Vec3::X;
            let w = a.angular_inverse_mass(axis) + b.angular_inverse_mass(axis);
            let impulse = part.impulse(tau, w) * axis;
            a.apply_angular_impulse(-impulse);
            b.apply_angular_impulse(impulse);
        } else if self.alpha_twist > 0.0 {
            // Soft twist (eq. 12-13): remove alpha_t of tau about t_b.
            let (fa, fb) = (a.orientation * self.frame_a, b.orientation * self.frame_b);
            let tau = measure_twist(self.twist_mode, fa, fb);
            relative_rotation(a, b, -self.alpha_twist * tau * (fb * Vec3::X));
        }
    }

    /// The hard curve (eq. 6) and length (eq. 9): the length measured on the frames the curve
    /// left, or, with [`BendTwist::Block`] and the paper's [`LengthCorrection::Offset`], on the
    /// same frames as the curve (their block is diagonal: see [`BendTwist::Block`]).
    #[inline(always)]
    fn curve_and_length(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        let (fa, fb) = (a.orientation * self.frame_a, b.orientation * self.frame_b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let (pa, pb) = (a.position, b.position);
        let shared = self.bend_twist == BendTwist::Block
            && self.length_correction == LengthCorrection::Offset;
        let length = shared.then(|| {
            let c = length_error(pa, ta, pb, tb, self.rest_length);
            (c, offset_axis(pa, pb, ta))
        });
        // Hard curve (eq. 6), full gradient.
        let (c, g) = curve_projection(pa, ta, pb, tb);
        if c > 1e-7 {
            let w = (a.inverse_mass + b.inverse_mass) * g.p_b.length_squared()
                + a.angular_inverse_mass(g.theta_a)
                + b.angular_inverse_mass(g.theta_b);
            if w > 0.0 {
                let lambda = -c / w;
                a.apply_linear_impulse(lambda * g.p_a);
                b.apply_linear_impulse(lambda * g.p_b);
                a.apply_angular_impulse(lambda * g.theta_a);
                b.apply_angular_impulse(lambda * g.theta_b);
            }
        }
        // Hard length (eq. 9), linear motion along o^ at fixed psi.
        match length {
            Some((c, axis)) => correct_length(a, b, c, axis, Vec3::ZERO),
            None => self.solve_length(a, b),
        }
    }

    /// The hard length part of [`RodRow::solve`] (eq. 9) on the current frames: linear motion
    /// along o^ at fixed psi (plus the turn through psi with [`LengthCorrection::Gradient`]).
    fn solve_length(&self, a: &mut SolverBody, b: &mut SolverBody) {
        let (fa, fb) = (a.orientation * self.frame_a, b.orientation * self.frame_b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let (pa, pb) = (a.position, b.position);
        let c = length_error(pa, ta, pb, tb, self.rest_length);
        let axis = offset_axis(pa, pb, ta);
        // angular part of the gradient: zero for the paper's correction
        let g_theta_b = match self.length_correction {
            LengthCorrection::Offset => Vec3::ZERO,
            LengthCorrection::Gradient => {
                let bend_axis = ta.cross(tb).try_normalize().unwrap_or(Vec3::ZERO);
                -self.rest_length * chord_ratio_derivative(angle_between(ta, tb)) * bend_axis
            }
        };
        correct_length(a, b, c, axis, g_theta_b);
    }
}

/// Removes the length error `c` (eq. 9) by linear motion along the offset direction `axis`, and
/// turns through psi along `g_theta_b` (zero for the paper's correction).
fn correct_length(a: &mut SolverBody, b: &mut SolverBody, c: f32, axis: Vec3, g_theta_b: Vec3) {
    let w = a.inverse_mass
        + b.inverse_mass
        + a.angular_inverse_mass(g_theta_b)
        + b.angular_inverse_mass(g_theta_b);
    if c.abs() > 1e-9 && w > 0.0 {
        let lambda = c / w;
        a.apply_linear_impulse(lambda * axis);
        b.apply_linear_impulse(-lambda * axis);
        if g_theta_b != Vec3::ZERO {
            a.apply_angular_impulse(lambda * g_theta_b);
            b.apply_angular_impulse(-lambda * g_theta_b);
        }
    }
}
