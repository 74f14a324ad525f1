//! Checks of one item each (a ragdoll, a rod, a joint, a body, the kinematics block, a
//! stiffness set), called by [`Scene::check`](super::Scene) with the item's field path.

use super::bounds::{self, Failure};
use super::locate::Seg;
use super::{
    BodyDef, JointDef, KindDef, KinematicsDef, RagdollDef, RodDef, SceneDef, ShapeKind,
    StiffnessDef,
};
use crate::math::Vec3;
use crate::ragdoll::joint_names;

/// One `[[ragdoll]]`: springs, alphas and stiffness, bounds, and the joints, parts and
/// forces it names; `at` gives a field's path.
pub(super) fn check_ragdoll(r: &RagdollDef, at: impl Fn(&str) -> Vec<Seg>) -> Result<(), Failure> {
    for (field, value) in [
        ("spine_spring", r.spine_spring),
        ("limb_spring", r.limb_spring),
    ] {
        check_relaxation(value).map_err(|m| (at(field), m))?;
    }
    for (field, value) in [("alpha_b", r.alpha_b), ("alpha_t", r.alpha_t)] {
        check_relaxation(value).map_err(|m| (at(field), m))?;
    }
    r.stiffness()
        .check(r.alpha_b.is_some(), r.alpha_t.is_some())
        .map_err(|(f, m)| (at(f), m))?;
    bounds::check_ragdoll(r, &at)?;
    let joints = joint_names(r.spine);
    for joint in r.pose.keys() {
        if !joints.contains(&joint.as_str()) {
            let mut p = at("pose");
            p.push(Seg::Key(joint.clone()));
            return Err((
                p,
                format!(
                    "unknown joint \"{joint}\" for spine {}, expected one of {}",
                    r.spine,
                    joints.join(", ")
                ),
            ));
        }
    }
    let parts = crate::ragdoll::part_names(r.spine);
    for part in r.forces.keys() {
        if !parts.contains(&part.as_str()) {
            let mut p = at("forces");
            p.push(Seg::Key(part.clone()));
            return Err((
                p,
                format!(
                    "unknown part \"{part}\", expected one of {}",
                    parts.join(", ")
                ),
            ));
        }
    }
    for part in &r.fixed {
        if !parts.contains(&part.as_str()) {
            return Err((
                at("fixed"),
                format!(
                    "unknown part \"{part}\", expected one of {}",
                    parts.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// One `[[rod]]` between two named bodies: rest length, alphas and stiffness.
pub(super) fn check_rod(
    r: &RodDef,
    body_names: &Names,
    at: impl Fn(&str) -> Vec<Seg>,
) -> Result<(), Failure> {
    check_pair(&r.a, &r.b, body_names).map_err(|(f, m)| (at(f), m))?;
    if let Some(l) = r
        .rest_length
        .filter(|l| !(*l > 0.0 && *l <= bounds::MAX_SIZE))
    {
        return Err((
            at("rest_length"),
            format!("must be a positive length, got {l}"),
        ));
    }
    check_relaxation(Some(r.alpha_b)).map_err(|m| (at("alpha_b"), m))?;
    check_relaxation(Some(r.alpha_t)).map_err(|m| (at("alpha_t"), m))?;
    // a normal along the tangent, or zero, gets a stand-in; NaN or infinity has no direction
    bounds::within(&r.normal, bounds::MAX_COORDINATE, "components")
        .map_err(|m| (at("normal"), m))?;
    r.stiffness()
        .check(r.alpha_b != 0.0, r.alpha_t != 0.0)
        .map_err(|(f, m)| (at(f), m))?;
    Ok(())
}

/// One `[[joint]]` between two named bodies: bounds, spring, axis, and its limits.
pub(super) fn check_joint(
    j: &JointDef,
    body_names: &Names,
    at: impl Fn(&str) -> Vec<Seg>,
) -> Result<(), Failure> {
    check_pair(&j.a, &j.b, body_names).map_err(|(f, m)| (at(f), m))?;
    bounds::check_joint(j).map_err(|(f, m)| (at(f), m))?;
    check_relaxation(j.spring).map_err(|m| (at("spring"), m))?;
    if Vec3::from(j.axis).length() < 1e-6 {
        return Err((at("axis"), "must be a non-zero vector".into()));
    }
    if j.hinge.is_some() && (j.swing.is_some() || j.twist.is_some()) {
        return Err((at("hinge"), "a hinge excludes swing and twist".into()));
    }
    if let Some([lo, hi]) = j.twist.or(j.hinge) {
        if lo > hi {
            let f = if j.hinge.is_some() { "hinge" } else { "twist" };
            return Err((at(f), format!("range [{lo}, {hi}] has min above max")));
        }
    }
    if matches!(j.swing, Some(s) if s < 0.0) {
        return Err((at("swing"), "must not be negative".into()));
    }
    Ok(())
}

/// The `[kinematics]` block (Fig. 6): a chain's length, joint count and shares, and nothing
/// simulated beside it.
pub(super) fn check_kinematics(k: &KinematicsDef, d: &SceneDef) -> Result<(), Failure> {
    let field = |f: &str| vec![Seg::Key("kinematics".into()), Seg::Key(f.into())];
    if !(k.length > 0.0 && k.length <= bounds::MAX_SIZE) {
        return Err((
            field("length"),
            format!(
                "must be positive, at most {} m, got {}",
                bounds::MAX_SIZE,
                k.length
            ),
        ));
    }
    if !(1..=1000).contains(&k.joints) {
        return Err((
            field("joints"),
            format!("must lie in [1, 1000], got {}", k.joints),
        ));
    }
    if !(k.max_bend.abs() <= bounds::MAX_DEGREES) {
        return Err((
            field("max_bend"),
            format!("must be a finite angle (deg), got {}", k.max_bend),
        ));
    }
    if k.unequal.len() != k.joints
        || k.unequal.iter().any(|w| !(*w >= 0.0 && w.is_finite()))
        || k.unequal.iter().sum::<f32>() <= 0.0
    {
        return Err((
            field("unequal"),
            format!("needs {} non-negative shares with a positive sum", k.joints),
        ));
    }
    if !d.ragdoll.is_empty() || !d.body.is_empty() {
        return Err((
            field("joints"),
            "a kinematics scene simulates nothing: remove its ragdolls and bodies".into(),
        ));
    }
    Ok(())
}

impl StiffnessDef {
    /// Positive stiffness, damping only beside one, and neither beside the alpha it replaces
    /// (`alpha_b`, `alpha_t`: whether the file sets them).
    pub(super) fn check(&self, alpha_b: bool, alpha_t: bool) -> Result<(), (&'static str, String)> {
        let parts = [
            (
                "bend_stiffness",
                "bend_damping",
                "alpha_b",
                alpha_b,
                self.bend_stiffness,
                self.bend_damping,
            ),
            (
                "twist_stiffness",
                "twist_damping",
                "alpha_t",
                alpha_t,
                self.twist_stiffness,
                self.twist_damping,
            ),
        ];
        for (stiffness_field, damping_field, alpha_field, alpha, stiffness, damping) in parts {
            match stiffness {
                Some(k) if !(k > 0.0 && k.is_finite()) => {
                    return Err((
                        stiffness_field,
                        format!("must be a positive stiffness in N m/rad, got {k}"),
                    ))
                }
                Some(_) if alpha => {
                    return Err((
                        stiffness_field,
                        format!("replaces {alpha_field}: set one of them, not both"),
                    ))
                }
                None if damping.is_some() => {
                    return Err((
                        damping_field,
                        format!("damps the {stiffness_field}, which is not set"),
                    ))
                }
                _ => {}
            }
            if let Some(c) = damping.filter(|c| !(*c >= 0.0 && c.is_finite())) {
                return Err((
                    damping_field,
                    format!("must be 0 or more N m s/rad, got {c}"),
                ));
            }
        }
        Ok(())
    }
}

/// Names seen so far: in order, for messages, and hashed, so that checking a scene of many
/// bodies stays linear in their number.
#[derive(Default)]
pub(super) struct Names<'a> {
    order: Vec<&'a str>,
    set: std::collections::HashSet<&'a str>,
}

impl<'a> Names<'a> {
    /// Whether `name` was seen.
    pub(super) fn contains(&self, name: &str) -> bool {
        self.set.contains(name)
    }

    /// Adds `name`.
    pub(super) fn push(&mut self, name: &'a str) {
        if self.set.insert(name) {
            self.order.push(name);
        }
    }

    /// The names for a message, in order: the first [`LISTED_NAMES`], then how many more.
    fn listed(&self) -> String {
        let shown = self.order.iter().take(LISTED_NAMES).copied();
        let mut list = shown.collect::<Vec<_>>().join(", ");
        if self.order.len() > LISTED_NAMES {
            list += &format!(" and {} more", self.order.len() - LISTED_NAMES);
        }
        list
    }
}

/// Names a message lists at most.
const LISTED_NAMES: usize = 40;

pub(super) fn check_name(name: &str, seen: &Names) -> Result<(), String> {
    if name.is_empty() || name.contains('/') {
        return Err(format!(
            "\"{name}\" is not a valid name (non-empty, no '/')"
        ));
    }
    if seen.contains(name) {
        return Err(format!("duplicate name \"{name}\""));
    }
    Ok(())
}

/// The two ends of a joint or rod: known bodies, and not the same one.
pub(super) fn check_pair(
    a: &str,
    b: &str,
    body_names: &Names,
) -> Result<(), (&'static str, String)> {
    for (field, name) in [("a", a), ("b", b)] {
        if !body_names.contains(name) {
            let known = body_names.listed();
            return Err((
                field,
                format!("unknown body \"{name}\", expected one of: {known}"),
            ));
        }
    }
    if a == b {
        return Err(("b", "needs two different bodies".into()));
    }
    Ok(())
}

pub(super) fn check_relaxation(value: Option<f32>) -> Result<(), String> {
    match value {
        Some(v) if !(0.0..=1.0).contains(&v) => {
            Err(format!("relaxation must lie in [0, 1], got {v}"))
        }
        _ => Ok(()),
    }
}

pub(super) fn check_body(b: &BodyDef) -> Result<(), (&'static str, String)> {
    let positive = |field: &'static str, v: Option<f32>| match v {
        None => Err((
            field,
            format!("required for a {:?} shape", b.shape).to_lowercase(),
        )),
        Some(x) if !(x > 0.0) => Err((field, format!("must be positive, got {x}"))),
        Some(_) => Ok(()),
    };
    match b.shape {
        ShapeKind::Sphere => positive("radius", b.radius)?,
        ShapeKind::Capsule => {
            positive("radius", b.radius)?;
            positive("half_height", b.half_height)?;
        }
        ShapeKind::Box => match b.half_extents {
            None => return Err(("half_extents", "required for a box shape".into())),
            Some(h) if h.iter().any(|&x| !(x > 0.0)) => {
                return Err(("half_extents", format!("must be positive, got {h:?}")))
            }
            Some(_) => {}
        },
        ShapeKind::Plane if b.kind != KindDef::Fixed => {
            return Err(("kind", "a plane (half-space) must be fixed".into()))
        }
        ShapeKind::Plane => {}
    }
    if matches!(b.restitution, Some(e) if !(0.0..=1.0).contains(&e)) {
        return Err(("restitution", "must lie in [0, 1]".into()));
    }
    for (field, value) in [
        ("static_friction", b.static_friction),
        ("dynamic_friction", b.dynamic_friction),
    ] {
        if matches!(value, Some(mu) if !(mu >= 0.0 && mu.is_finite())) {
            return Err((field, "must be a non-negative number".into()));
        }
    }
    if b.kind == KindDef::Dynamic {
        match (b.mass, b.density) {
            (Some(_), Some(_)) => return Err(("density", "give mass or density, not both".into())),
            (None, None) => {
                return Err(("mass", "a dynamic body needs a mass or a density".into()))
            }
            (Some(m), None) if !(m > 0.0 && m.is_finite()) => {
                return Err((
                    "mass",
                    format!("a dynamic body needs a positive mass, got {m}"),
                ))
            }
            (None, Some(rho)) if !(rho > 0.0 && rho.is_finite()) => {
                return Err((
                    "density",
                    format!("a dynamic body needs a positive density, got {rho}"),
                ))
            }
            _ => {}
        }
    }
    Ok(())
}
