//! The contact options beside the paper's hard projection: soft contacts ([`Softness`]) and
//! mass scaling by height ([`Stacking`]).

use crate::math::Vec3;

/// Soft contacts: a contact point as a damped spring of `hertz` natural frequency and
/// `damping_ratio` (Box2D v3's contact softness, solved here in XPBD's compliance form, Macklin
/// et al. 2016). With `w` a point's inverse effective mass, omega = 2 pi hertz and substep `h`:
/// stiffness `k = omega^2 / w` and damping `c = 2 zeta omega / w`, so XPBD's
/// `alpha~ = 1 / (k h^2) = w / (omega h)^2` and `gamma = c / (k h) = 2 zeta / (omega h)`, and
/// each iteration's impulse is `-(C + alpha~ P + gamma (C - C_0)) / ((1 + gamma) w + alpha~)`.
/// The stiffness scales with the point's effective mass, so a soft contact sags the same
/// under any load of its own weight (`g / omega^2`: 0.28 mm at 30 Hz). `hertz = 0` is the
/// paper's hard projection.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Softness {
    /// Natural frequency (Hz); 0: hard contact.
    pub hertz: f32,
    /// Damping ratio zeta (1: critical).
    pub damping_ratio: f32,
}

impl Softness {
    /// `(1 / (omega h)^2, 2 zeta / (omega h))`, or zeros for a hard contact.
    pub fn substep_constants(self, h: f32) -> (f32, f32) {
        if self.hertz <= 0.0 {
            return (0.0, 0.0);
        }
        let omega_h = std::f32::consts::TAU * self.hertz * h;
        (
            1.0 / (omega_h * omega_h),
            2.0 * self.damping_ratio / omega_h,
        )
    }
}

/// Stacking: PBD's mass scaling by height (Macklin et al. 2014, `m* = m e^(-k h)`, the
/// contact solve only). In a contact, the lower body (its centre along `up`, against gravity)
/// counts `e^(k dh)` times heavier than its true mass, `dh` the height of the other body's
/// centre above its own. `k = 0` (the default) is the paper's contact.
///
/// Gauss-Seidel carries a load down a stack only as fast as the mass ratios let it: a light
/// limb under a whole ragdoll is pushed down by most of each correction and the floor pushes it
/// back, so the pile's weight never reaches the floor in a fixed number of sweeps (a 1.7 kg
/// forearm stayed 7 cm inside a thigh for 40 frames of the drop). Making the lower body heavier
/// for the contact lifts the upper body instead, as shock propagation does (Guendelman et al.
/// 2003, the lower body infinitely heavy). The scale comes from each body's height, so every
/// body has one mass in all its contacts: a variant that weighted each point by how vertical
/// its normal was gave a body wedged between two others a different mass in each contact, and
/// the sweeps then pumped energy (a ragdoll thrown 12 m up in the drop). The price: a stacked
/// pair's impulses do not conserve its momentum, and the lower body feels less of the load.
///
/// `max_ratio` caps `e^(k dh)`: at 20 substeps of one iteration, uncapped ratios (e^4 for a
/// limb 40 cm under a chest) had the sweeps pump a few piles until a limb exploded, and deep
/// overlap came with them; capped at e, 4 of 256 drop landings passed 1 cm where 12 did (20
/// substeps of one iteration with contacts found every substep, cheap joints and three sweeps;
/// docs/landings.md, The box's nearest point, and stacking's ratio capped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stacking {
    /// Unit vector against gravity (zero without gravity: no scaling).
    pub up: Vec3,
    /// `k` (1/m).
    pub rate: f32,
    /// The most times heavier the lower body counts (1 or more; infinite: no cap).
    pub max_ratio: f32,
}

impl Default for Stacking {
    fn default() -> Self {
        Stacking {
            up: Vec3::ZERO,
            rate: 0.0,
            max_ratio: f32::INFINITY,
        }
    }
}

impl Stacking {
    /// The scales of body a's and body b's inverse mass in a contact, from their centres.
    pub fn scales(self, centre_a: Vec3, centre_b: Vec3) -> (f32, f32) {
        let height = (centre_b - centre_a).dot(self.up);
        if self.rate == 0.0 || height == 0.0 {
            return (1.0, 1.0);
        }
        let lower = crate::math::exp(-self.rate * height.abs()).max(self.max_ratio.recip());
        if height > 0.0 {
            (lower, 1.0) // b above a
        } else {
            (1.0, lower)
        }
    }
}
