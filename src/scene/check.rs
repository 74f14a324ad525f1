//! Semantic checks serde cannot express: bounds, names, pairs, shapes. Each failure is a
//! field path and a message; [`Scene::parse`] turns it into `FILE:LINE: FIELD: message`.

use super::bounds::{self, Failure};
use super::check_items::{
    check_body, check_joint, check_kinematics, check_name, check_ragdoll, check_relaxation,
    check_rod, Names,
};
use super::locate::Seg;
use super::{variant, BodyDef, KindDef, Scene, SceneDef, ShapeKind, TileDef};
use crate::world::Settings;

impl Scene {
    /// The `[[tile]]` groups, before they are expanded: sizes, names, and fixed bodies only.
    pub(super) fn check_tiles(&self) -> Result<(), Failure> {
        let d = &self.def;
        let at = |i: usize, field: &str| {
            vec![
                Seg::Key("tile".into()),
                Seg::Index(i),
                Seg::Key(field.into()),
            ]
        };
        let mut tile_names = Names::default();
        let mut made = 0;
        for (i, t) in d.tile.iter().enumerate() {
            check_name(&t.name, &tile_names).map_err(|m| (at(i, "name"), m))?;
            tile_names.push(&t.name);
            if t.repeat.contains(&0) {
                return Err((
                    at(i, "repeat"),
                    format!(
                        "copies along x and z must be at least 1, got {:?}",
                        t.repeat
                    ),
                ));
            }
            if t.spacing.iter().any(|s| !(*s > 0.0 && s.is_finite())) {
                return Err((
                    at(i, "spacing"),
                    format!("must be positive distances (m), got {:?}", t.spacing),
                ));
            }
            if t.body.is_empty() {
                return Err((at(i, "body"), "needs at least one [[tile.body]]".into()));
            }
            // the bound is on all groups together: each group within it is not enough
            made += bounds::tile_bodies(t.repeat, t.body.len());
            if made > bounds::MAX_TILE_BODIES {
                let max = bounds::MAX_TILE_BODIES;
                let message = match i {
                    0 => format!("makes {made} bodies, more than {max}"),
                    _ => format!(
                        "makes the [[tile]] groups' bodies {made} together, more than {max}"
                    ),
                };
                return Err((at(i, "repeat"), message));
            }
            let mut names = Names::default();
            for (j, b) in t.body.iter().enumerate() {
                let field = |f: &str| {
                    vec![
                        Seg::Key("tile".into()),
                        Seg::Index(i),
                        Seg::Key("body".into()),
                        Seg::Index(j),
                        Seg::Key(f.into()),
                    ]
                };
                check_name(&b.name, &names).map_err(|m| (field("name"), m))?;
                names.push(&b.name);
                self.check_tile_body(t, b).map_err(|(f, m)| (field(f), m))?;
            }
        }
        Ok(())
    }

    /// One body of a tile (`t`): fixed, bounded, valid, and not named as a copy would be.
    fn check_tile_body(&self, t: &TileDef, b: &BodyDef) -> Result<(), (&'static str, String)> {
        let d = &self.def;
        if b.kind != KindDef::Fixed {
            return Err((
                "kind",
                "a tile copies static geometry: kind must be \"fixed\"".into(),
            ));
        }
        if b.shape == ShapeKind::Plane {
            return Err((
                "shape",
                "a plane is unbounded: give it as one [[body]], not in a tile".into(),
            ));
        }
        check_body(b)?;
        bounds::check_body(b, d.max_speed, d.max_angular_speed)?;
        let copy = t.copy_name(0, 0, &b.name);
        if let Some(other) = d.body.iter().find(|other| other.name == copy) {
            return Err((
                "name",
                format!(
                    "its copies are named {}_<i>_<k>_{}, and body \"{}\" already exists",
                    t.name, b.name, other.name
                ),
            ));
        }
        Ok(())
    }

    /// The scene's own settings (time step, counts, bounds, recording, name): checked first,
    /// before the items that depend on them (a body's velocity against `max_speed`).
    pub(super) fn check_method(&self) -> Result<(), Failure> {
        let d = &self.def;
        check_settings(d, &[])?;
        let every = d.record.every;
        if !(1..=bounds::MAX_FRAMES).contains(&every) {
            return Err((
                vec![Seg::Key("record".into()), Seg::Key("every".into())],
                format!(
                    "must be at least 1 (every frame) and at most {}, got {every}",
                    bounds::MAX_FRAMES
                ),
            ));
        }
        if let Some(name) = &d.name {
            bounds::check_scene_name(name).map_err(|m| (vec![Seg::Key("name".into())], m))?;
        }
        Ok(())
    }

    /// Semantic checks serde cannot express.
    pub(super) fn check(&self) -> Result<(), Failure> {
        let d = &self.def;
        let at = |list: &str, i: usize, field: &str| {
            vec![Seg::Key(list.into()), Seg::Index(i), Seg::Key(field.into())]
        };
        self.check_method()?;
        let mut variants: Vec<&str> = Vec::new();
        for (i, v) in d.variant.iter().enumerate() {
            let name = v.name.as_deref();
            variant::check_variant_name(name, &variants).map_err(|m| match name {
                Some(_) => (at("variant", i, "name"), m),
                None => (vec![Seg::Key("variant".into()), Seg::Index(i)], m),
            })?;
            variants.extend(name);
            let prefix = [Seg::Key("variant".into()), Seg::Index(i)];
            check_settings(&v.applied_to(d), &prefix)?;
        }
        if let Some(k) = &d.kinematics {
            check_kinematics(k, d)?;
        }
        let mut names = Names::default();
        for (i, r) in d.ragdoll.iter().enumerate() {
            check_name(&r.name, &names).map_err(|m| (at("ragdoll", i, "name"), m))?;
            names.push(&r.name);
            if !r.spine.fits_humanoid() {
                let m = "rig is a game character's spine; a ragdoll takes chain3, rod or single";
                return Err((at("ragdoll", i, "spine"), m.into()));
            }
            check_ragdoll(r, |f| at("ragdoll", i, f))?;
        }
        for (i, c) in d.character.iter().enumerate() {
            check_name(&c.name, &names).map_err(|m| (at("character", i, "name"), m))?;
            names.push(&c.name);
            if !c.spine.fits_character() {
                let m = "chain3 is the reference humanoid's spine; a character takes rig, rod or single";
                return Err((at("character", i, "spine"), m.into()));
            }
            bounds::check_character(c, |f| at("character", i, f))?;
            bounds::check_playback(c, d.dt, |f| at("character", i, f))?;
            for (field, alpha) in [("alpha_b", c.alpha_b), ("alpha_t", c.alpha_t)] {
                check_relaxation(Some(alpha)).map_err(|m| (at("character", i, field), m))?;
            }
        }
        let mut body_names = Names::default();
        for (i, b) in d.body.iter().enumerate() {
            check_name(&b.name, &body_names).map_err(|m| (at("body", i, "name"), m))?;
            body_names.push(&b.name);
            check_body(b).map_err(|(field, m)| (at("body", i, field), m))?;
            bounds::check_body(b, d.max_speed, d.max_angular_speed)
                .map_err(|(field, m)| (at("body", i, field), m))?;
        }
        for (i, r) in d.rod.iter().enumerate() {
            check_name(&r.name, &names).map_err(|m| (at("rod", i, "name"), m))?;
            names.push(&r.name);
            check_rod(r, &body_names, |f| at("rod", i, f))?;
        }
        let mut joint_names_seen = Names::default();
        for (i, j) in d.joint.iter().enumerate() {
            check_name(&j.name, &joint_names_seen).map_err(|m| (at("joint", i, "name"), m))?;
            joint_names_seen.push(&j.name);
            check_joint(j, &body_names, |f| at("joint", i, f))?;
        }
        Ok(())
    }
}

/// The scene's settings (a variant's too, with `prefix` its path): each method setting within
/// its declared bounds, then the world's (counts, bounds, damping).
fn check_settings(d: &SceneDef, prefix: &[Seg]) -> Result<(), Failure> {
    let at = |field: &str| {
        let mut path = prefix.to_vec();
        path.push(Seg::Key(field.into()));
        path
    };
    let mut method = Settings::default();
    d.write_method_settings(&mut method);
    method
        .check_method()
        .map_err(|(field, message)| (at(field), message))?;
    let non_negative = |x: f32| x >= 0.0 && x.is_finite();
    let ci_frames = d.ci_frames.unwrap_or(1);
    // (field, whether it holds, what to say when it does not), checked in this order
    let rules = [
        ("frames", d.frames > 0, "must be at least 1".into()),
        (
            "ci_frames",
            (1..=d.frames).contains(&ci_frames),
            format!("must lie in [1, frames = {}], got {ci_frames}", d.frames),
        ),
        ("max_speed", d.max_speed > 0.0, "must be positive".into()),
        (
            "damping",
            d.damping.iter().all(|&c| non_negative(c)),
            format!("rates must be non-negative, got {:?}", d.damping),
        ),
        (
            "max_separation",
            d.max_separation > 0.0,
            format!(
                "must be a positive distance in m (or inf), got {}",
                d.max_separation
            ),
        ),
        (
            "max_penetration",
            d.max_penetration > 0.0,
            format!(
                "must be a positive distance in m (or inf), got {}",
                d.max_penetration
            ),
        ),
        (
            "max_angular_speed",
            d.max_angular_speed > 0.0,
            "must be positive".into(),
        ),
    ];
    if let Some((field, _, message)) = rules.into_iter().find(|(_, holds, _)| !holds) {
        return Err((at(field), message));
    }
    bounds::check_settings(d, prefix)
}
