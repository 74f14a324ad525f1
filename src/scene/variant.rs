//! Method variants of a scene: `[[variant]]` tables that the main job records beside the
//! scene's own method, e.g. the drop at a game engine's settings next to the paper's. A variant
//! is read as [`Overrides`] with a name: the main job records the scene once more per variant,
//! as `<scene>_<name>` (per spine, with the spine's name after it); `rodlab run SCENE
//! --variant NAME` runs it alone.

use super::{Overrides, Scene, SceneDef};

impl Overrides {
    /// The scene's settings with this variant applied, for checking.
    pub(super) fn applied_to(&self, def: &SceneDef) -> SceneDef {
        let mut def = def.clone();
        def.variant.clear();
        self.apply(&mut def);
        def
    }
}

/// A variant name: given, non-empty, `[a-z0-9_]`, not taken.
pub(super) fn check_variant_name(name: Option<&str>, taken: &[&str]) -> Result<(), String> {
    let Some(name) = name else {
        return Err("a [[variant]] needs a name or a method (it names a recording)".into());
    };
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
    {
        return Err(format!(
            "must be lower-case letters, digits and underscores (it names a recording), got {name:?}"
        ));
    }
    if taken.contains(&name) {
        return Err(format!(
            "a variant named {name:?} comes earlier in this file"
        ));
    }
    Ok(())
}

impl Scene {
    /// The scene at its variant `name`, named `<scene>_<name>`.
    pub fn variant(&self, name: &str) -> anyhow::Result<Scene> {
        let Some(variant) = (self.def.variant.iter()).find(|v| v.name.as_deref() == Some(name))
        else {
            let known: Vec<&str> = self.variant_names().collect();
            anyhow::bail!(
                "{}: no [[variant]] named {name:?} (the file has {})",
                self.path.display(),
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            );
        };
        let mut scene = self.clone();
        scene.def = variant.applied_to(&self.def);
        scene.def.name = Some(format!("{}_{name}", self.name()));
        Ok(scene)
    }

    /// The names of the scene's `[[variant]]`s, in file order (every variant has one once the
    /// scene is checked).
    pub fn variant_names(&self) -> impl Iterator<Item = &str> {
        self.def.variant.iter().filter_map(|v| v.name.as_deref())
    }
}
