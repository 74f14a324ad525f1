//! The rod constraint (paper §5): an inextensible Kirchhoff rod between bodies a and b, shaped as
//! a circular arc, with soft bending and twisting. All parts are solved in one function (§7).
//!
//! Ends at the centres of mass, frames fixed in the bodies (eq. 2):
//! `gamma(0) = p_a`, `gamma(1) = p_b`, `F(0) = q_a F_a`, `F(1) = q_b F_b`; the body tangents
//! `t_i = F(i) x` and normals `F(i) y`. With the offset `o = p_b - p_a`, `o^ = o / |o|` and the
//! bend angle `psi = acos(t_a . t_b)`:
//!
//! - curve (eq. 6), hard: `C_curve = t_a + t_b - 2 (t_a . o^) o^ = 0`, i.e. `t_b = S t_a` with
//!   `S = 2 o^ o^T - E` the half turn about `o^`. We solve its scalar form
//!   `C = angle(t_b, r)`, `r = S t_a`, with `n = (t_b x r) / |t_b x r|`, `m = n x r`:
//!   `dC/dtheta_a = S n`, `dC/dtheta_b = -n`,
//!   `dC/dp_b = -dC/dp_a = g_o = (2 / |o|) (E - o^ o^T) ((t_a . o^) m + (m . o^) t_a)`.
//!   The full gradient (rotations and positions) keeps the pair's momentum: `C` is invariant
//!   under moving and turning the pair together.
//! - length (eq. 9), hard: `C_len = |p_b - p_a| - 2 l_0 sin(psi/2) / psi`, corrected by linear
//!   motion along `o^` only, at fixed `psi`, as the paper does.
//! - bend (eq. 11), soft: `C_bend = alpha_b psi^2 / (2 l_0^2)`; each iteration removes the
//!   fraction `alpha_b` of `psi` by equal and opposite turns about `t_a x t_b`
//!   (`alpha_b = 0`: free bending; `1`: straight).
//! - twist (eq. 12-13), soft: `C_twist = alpha_t tau^2 / 2`; each iteration removes the fraction
//!   `alpha_t` of `tau` by equal and opposite turns about `t_b`. `tau` is measured
//!   ([`TwistMode::Exact`]) as the signed turn about `t_b` left between `F(1)` and `F(0)`
//!   carried along the arc (the bend by `psi` about `t_a x t_b`, the natural frame's parallel
//!   transport), or ([`TwistMode::Paper`]) as eq. 12, `tau = xi - psi` with `xi` the total
//!   angle between `F(0)` and `F(1)`: it has no sign (we take the sign from the exact twist) and
//!   underestimates a twist on a bent rod.
//!
//! Stiffness in physical units (an alternative to the alphas, not in the paper): the fraction
//! alpha removed per iteration makes the same alpha stiffer at more iterations, substeps or a
//! shorter step. With `bend_stiffness` k (N m/rad) the bend is instead the compliant constraint
//! `C = psi` of energy `k psi^2 / 2`, solved in compliance form (XPBD, Macklin, Mueller and
//! Chentanez 2016, eq. 18): per substep of `h`, with `alpha~ = 1 / (k h^2)` and the multiplier
//! `lambda` reset to 0, each iteration applies
//! `d lambda = (-psi - alpha~ lambda) / (w + alpha~)`
//! as the angular impulse `d lambda (t_a x t_b)^` on b and its negative on a, `w` the pair's
//! inverse inertia about that axis. The twist likewise with `C = tau` about `t_b`
//! (`twist_stiffness`). Once the iterations converge, the rod holds the torque `k psi` whatever
//! their number (`tests/it/rod.rs` measures it). Damping `c` (N m s/rad) acts on the velocities
//! after the substep ([`RodRow::damp_velocities`]).
//!
//! The arc (eq. 7-8, in a form stable at small `psi`): with `k` the unit normal of `t_a` toward
//! `t_b`, `gamma(s) = p_a + l_0 (sin(psi s)/psi t_a + (1 - cos(psi s))/psi k)`, whose chord is
//! eq. 9. Its natural frame at `s` is `F(0)` turned by `psi s` about `t_a x t_b`; the material
//! frame adds the twist `tau s` about the tangent.

use super::parts::relative_rotation;
use super::Violation;
use crate::body::{Body, BodyId};
use crate::math::{angle_between, any_perpendicular, twist_angle, Mat3, Quat, Vec3};
use crate::solver_body::pair_mut;
use crate::solver_body::SolverBody;

/// How the length constraint (eq. 9) is corrected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LengthCorrection {
    /// The paper's: linear motion along o^ at fixed psi. Its force is not along the gradient of
    /// eq. 9, so on a freely bending rod it does work (`tests/it/rod.rs` measures the gain).
    #[default]
    Offset,
    /// Along the full gradient of eq. 9: also turns the bodies through psi,
    /// `dC/dtheta_b = -dC/dtheta_a = -l_0 c'(psi) (t_a x t_b)^`, with `c(psi) = 2 sin(psi/2)/psi`.
    Gradient,
}

/// How the twist angle tau is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TwistMode {
    /// Signed turn about the end tangent after parallel transport along the arc.
    #[default]
    Exact,
    /// The paper's eq. 12, `tau = xi - psi` (unsigned; underestimates on bent rods).
    Paper,
}

/// A rod part's stiffness in physical units, solved in compliance form (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Stiffness {
    /// Restoring torque per radian (N m/rad), > 0.
    pub stiffness: f32,
    /// Damping torque per rad/s of bend or twist rate (N m s/rad), >= 0.
    pub damping: f32,
}

/// A rod (§5) between two bodies' centres of mass: hard curve (eq. 6) and length (eq. 9), soft bend
/// (eq. 11) and twist (eq. 12-13).
#[derive(Clone, Debug)]
pub struct Rod {
    /// Name, for failure reports and recordings.
    pub name: String,
    /// Body at the rod's start, s = 0.
    pub body_a: BodyId,
    /// Body at the rod's end, s = 1.
    pub body_b: BodyId,
    /// Rod frame in each body (eq. 2): x is the body tangent, y the body normal.
    pub local_frame_a: Quat,
    /// Rod frame in body b (see `local_frame_a`).
    pub local_frame_b: Quat,
    /// Rest length l_0 (m).
    pub rest_length: f32,
    /// Bending relaxation alpha_b in [0, 1].
    pub alpha_bend: f32,
    /// Twisting relaxation alpha_t in [0, 1].
    pub alpha_twist: f32,
    /// Bending stiffness; when set it replaces `alpha_bend`.
    pub bend_stiffness: Option<Stiffness>,
    /// Twisting stiffness; when set it replaces `alpha_twist`.
    pub twist_stiffness: Option<Stiffness>,
    /// How tau is measured for the twist (eq. 12-13).
    pub twist_mode: TwistMode,
    /// How the length constraint (eq. 9) is corrected.
    pub length_correction: LengthCorrection,
}

/// Everything measured on a rod at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodState {
    /// Bend angle psi between the tangents t_a and t_b (rad).
    pub psi: f32,
    /// Twist angle tau (rad), measured by the rod's [`TwistMode`].
    pub tau: f32,
    /// eq. 9 (m).
    pub length_error: f32,
    /// angle between t_b and the reflection of t_a about o^ (rad).
    pub curve_error: f32,
}

impl Rod {
    /// Instantiates a rod at the bodies' current poses (§6): rest length `|p_b - p_a|` and both
    /// tangents along the offset, so the rod starts straight and every constraint holds.
    /// `normal_hint` picks the body normals (projected off the tangent).
    pub fn instantiate(
        name: impl Into<String>,
        bodies: &[Body],
        body_a: BodyId,
        body_b: BodyId,
        normal_hint: Vec3,
    ) -> Result<Rod, String> {
        let name = name.into();
        let (a, b) = (&bodies[body_a.index()], &bodies[body_b.index()]);
        let offset = b.position - a.position;
        let rest_length = offset.length();
        if !(rest_length > 1e-4) {
            return Err(format!("rod \"{name}\": the body centres coincide (rest length {rest_length} m); a rod needs a positive rest length"));
        }
        let tangent = offset / rest_length;
        let normal = (normal_hint - normal_hint.dot(tangent) * tangent)
            .try_normalize()
            .unwrap_or_else(|| any_perpendicular(tangent));
        let frame = Quat::from_mat3(&glam::Mat3::from_cols(
            tangent,
            normal,
            tangent.cross(normal),
        ))
        .normalize();
        Ok(Rod {
            name,
            body_a,
            body_b,
            local_frame_a: (a.orientation.inverse() * frame).normalize(),
            local_frame_b: (b.orientation.inverse() * frame).normalize(),
            rest_length,
            alpha_bend: 0.0,
            alpha_twist: 0.0,
            bend_stiffness: None,
            twist_stiffness: None,
            twist_mode: TwistMode::Exact,
            length_correction: LengthCorrection::Offset,
        })
    }

    /// World rod frames F(0), F(1) at the preview poses.
    pub fn frames(&self, a: &Body, b: &Body) -> (Quat, Quat) {
        (
            a.preview_orientation * self.local_frame_a,
            b.preview_orientation * self.local_frame_b,
        )
    }

    /// Twist tau (rad) between the world rod frames F(0) and F(1), by the rod's [`TwistMode`].
    pub fn twist(&self, frame_a: Quat, frame_b: Quat) -> f32 {
        measure_twist(self.twist_mode, frame_a, frame_b)
    }

    /// The prepare stage: the rod as the solver stores it.
    pub fn prepare(&self) -> RodRow {
        RodRow {
            body_a: self.body_a.0,
            body_b: self.body_b.0,
            frame_a: self.local_frame_a,
            frame_b: self.local_frame_b,
            rest_length: self.rest_length,
            alpha_bend: self.alpha_bend,
            alpha_twist: self.alpha_twist,
            bend_compliant: self.bend_stiffness.map(Compliant::new),
            twist_compliant: self.twist_stiffness.map(Compliant::new),
            twist_mode: self.twist_mode,
            length_correction: self.length_correction,
        }
    }

    /// Bend, twist, length error (eq. 9) and curve error (eq. 6) at the preview poses.
    pub fn state(&self, a: &Body, b: &Body) -> RodState {
        let (fa, fb) = self.frames(a, b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let (pa, pb) = (a.preview_position, b.preview_position);
        RodState {
            psi: angle_between(ta, tb),
            tau: self.twist(fa, fb),
            length_error: length_error(pa, ta, pb, tb, self.rest_length),
            curve_error: curve_error(pa, ta, pb, tb),
        }
    }

    /// Dislocation |C_len| (m) and the curve error (rad), the rod's hard constraints.
    pub fn violation(&self, a: &Body, b: &Body) -> Violation {
        let s = self.state(a, b);
        Violation {
            dislocation: s.length_error.abs(),
            angular: s.curve_error,
        }
    }

    /// Point gamma(s) and material frame F(s) of the arc at the current poses, s in [0, 1].
    /// The arc is built from p_a and t_a; any residual gap at p_b is shared linearly along s so
    /// the drawn curve always ends at both centres.
    pub fn sample(&self, a: &Body, b: &Body, s: f32) -> (Vec3, Quat) {
        let (fa, fb) = self.frames(a, b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let end = arc_point(a.preview_position, ta, tb, self.rest_length, 1.0);
        let gap = b.preview_position - end;
        let point = arc_point(a.preview_position, ta, tb, self.rest_length, s) + s * gap;
        let psi = angle_between(ta, tb);
        let bend_axis = ta
            .cross(tb)
            .try_normalize()
            .unwrap_or_else(|| any_perpendicular(ta));
        let natural = Quat::from_axis_angle(bend_axis, psi * s) * fa;
        let frame = natural * Quat::from_rotation_x(self.twist(fa, fb) * s);
        (point, frame.normalize())
    }
}

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
    fn new(stiffness: Stiffness) -> Self {
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
    pub fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        let (fa, fb) = (a.orientation * self.frame_a, b.orientation * self.frame_b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
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
        // Hard curve (eq. 6), full gradient.
        let (fa, fb) = (a.orientation * self.frame_a, b.orientation * self.frame_b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let (pa, pb) = (a.position, b.position);
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
}

/// tau by `mode` (see [`TwistMode`]).
pub fn measure_twist(mode: TwistMode, frame_a: Quat, frame_b: Quat) -> f32 {
    let exact = twist_exact(frame_a, frame_b);
    match mode {
        TwistMode::Exact => exact,
        TwistMode::Paper => twist_paper(frame_a, frame_b).copysign(exact),
    }
}

/// `2 sin(psi/2) / psi`, the chord of a unit-length arc bent by psi (eq. 9), with its series
/// `1 - psi^2/24 + psi^4/1920` near 0.
pub fn chord_ratio(psi: f32) -> f32 {
    if psi.abs() < 1e-2 {
        let p2 = psi * psi;
        1.0 - p2 / 24.0 + p2 * p2 / 1920.0
    } else {
        2.0 * (0.5 * psi).sin() / psi
    }
}

/// `d/dpsi (2 sin(psi/2) / psi)`, with its series `-psi/12 + psi^3/480` near 0.
pub fn chord_ratio_derivative(psi: f32) -> f32 {
    if psi.abs() < 1e-2 {
        -psi / 12.0 + psi * psi * psi / 480.0
    } else {
        (psi * (0.5 * psi).cos() - 2.0 * (0.5 * psi).sin()) / (psi * psi)
    }
}

/// Unit offset axis o^; along the tangents when the centres coincide.
pub fn offset_axis(pa: Vec3, pb: Vec3, ta: Vec3) -> Vec3 {
    (pb - pa).try_normalize().unwrap_or(ta)
}

/// The vector form of eq. 6: `t_a + t_b - 2 (t_a . o^) o^`.
pub fn curve_vector(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3) -> Vec3 {
    let o = offset_axis(pa, pb, ta);
    ta + tb - 2.0 * ta.dot(o) * o
}

/// Angle (rad) between t_b and the reflection `S t_a` of t_a about o^: the scalar form of eq. 6.
pub fn curve_error(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3) -> f32 {
    curve_projection(pa, ta, pb, tb).0
}

/// eq. 9: `|p_b - p_a| - 2 l_0 sin(psi/2) / psi`.
pub fn length_error(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3, rest_length: f32) -> f32 {
    (pb - pa).length() - rest_length * chord_ratio(angle_between(ta, tb))
}

/// Gradient of [`curve_error`] with respect to positions and rotation vectors of both bodies.
#[derive(Clone, Copy, Debug)]
pub struct CurveGradient {
    /// `dC/dp_a = -g_o` (rad/m).
    pub p_a: Vec3,
    /// `dC/dtheta_a = S n`, with respect to body a's rotation vector.
    pub theta_a: Vec3,
    /// `dC/dp_b = g_o` (rad/m).
    pub p_b: Vec3,
    /// `dC/dtheta_b = -n`, with respect to body b's rotation vector.
    pub theta_b: Vec3,
}

/// The gradient of [`curve_error`] (eq. 6) alone; see [`curve_projection`].
pub fn curve_gradient(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3) -> CurveGradient {
    curve_projection(pa, ta, pb, tb).1
}

/// [`curve_error`] and [`curve_gradient`] together, sharing the geometry (§7).
pub fn curve_projection(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3) -> (f32, CurveGradient) {
    let offset = pb - pa;
    let distance = offset.length();
    let o = if distance > 1e-12 {
        offset / distance
    } else {
        ta
    };
    let reflect = |v: Vec3| 2.0 * v.dot(o) * o - v;
    let r = reflect(ta);
    let cross = tb.cross(r);
    let sin = cross.length();
    let error = sin.atan2(tb.dot(r));
    let n = if sin > 1e-12 {
        cross / sin
    } else {
        any_perpendicular(tb)
    };
    let m = n.cross(r);
    let g_o = if distance > 1e-6 {
        let v = ta.dot(o) * m + m.dot(o) * ta;
        (2.0 / distance) * (v - v.dot(o) * o)
    } else {
        Vec3::ZERO
    };
    let gradient = CurveGradient {
        p_a: -g_o,
        theta_a: reflect(n),
        p_b: g_o,
        theta_b: -n,
    };
    (error, gradient)
}

/// A point of the arc from p_a with tangent t_a bent toward t_b, length `rest_length`, s in [0, 1].
pub fn arc_point(pa: Vec3, ta: Vec3, tb: Vec3, rest_length: f32, s: f32) -> Vec3 {
    let psi = angle_between(ta, tb);
    let k = (tb - ta.dot(tb) * ta)
        .try_normalize()
        .unwrap_or_else(|| any_perpendicular(ta));
    let (along, across) = if psi < 1e-3 {
        let ps = psi * s;
        (s * (1.0 - ps * ps / 6.0), s * ps * (0.5 - ps * ps / 24.0))
    } else {
        // 1 - cos x = 2 sin^2(x/2), without the cancellation of the left side in f32
        let half = (0.5 * psi * s).sin();
        ((psi * s).sin() / psi, 2.0 * half * half / psi)
    };
    pa + rest_length * (along * ta + across * k)
}

/// Signed twist about t_b: `F(1)` against `F(0)` carried along the arc by the minimal rotation
/// taking t_a to t_b.
pub fn twist_exact(frame_a: Quat, frame_b: Quat) -> f32 {
    let transport = Quat::from_rotation_arc(frame_a * Vec3::X, frame_b * Vec3::X);
    twist_angle((transport * frame_a).inverse() * frame_b, Vec3::X)
}

/// The paper's eq. 12: `tau = xi - psi`, xi the total angle between the two frames.
pub fn twist_paper(frame_a: Quat, frame_b: Quat) -> f32 {
    let xi = crate::math::rotation_vector(frame_a.inverse() * frame_b).length();
    xi - angle_between(frame_a * Vec3::X, frame_b * Vec3::X)
}
