//! What a run folder records about its scene, so that `e3d report` draws
//! the effects on the scene's own grid.
//!
//! `e3d run --out DIR` writes a [`SceneRecord`] into `summary.json` as
//! `scene_record`: where the scene came from (a file, made absolute, or a
//! built-in name), a hash of its content, and its effect grid (rows,
//! columns, bounds). `e3d report` draws from that record alone, never by
//! looking the scene's name up (a user's scene named like a built-in one,
//! or a scene edited since, would be drawn on another grid).
//!
//! ```
//! use e3d::report::run_scene::SceneRecord;
//! use e3d::Scene;
//! let scene = Scene::builtin("two_rooms").unwrap();
//! let r = SceneRecord::new(&scene, "two_rooms");
//! assert_eq!(r.path, "builtin:two_rooms");
//! assert_eq!((r.effect_grid.rows, r.effect_grid.cols), (3, 6));
//! assert!(r.check().is_ok());
//! ```

use crate::effect::EffectGrid;
use crate::Scene;
use serde::{Deserialize, Serialize};

/// The scene of a run, as `summary.json` records it (`scene_record`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneRecord {
    /// The scene's name.
    pub name: String,
    /// The scene file, made absolute, or `builtin:NAME` for a built-in
    /// scene.
    pub path: String,
    /// The hash of the scene's content ([`content_hash`]), 16 hex digits.
    pub content_hash: String,
    /// The scene's effect grid: rows, columns and the rectangle it covers.
    pub effect_grid: EffectGrid,
}

/// The hash of a scene's content: FNV-1a (64 bits) of its canonical RON
/// text ([`SceneSpec::to_ron`](crate::scene::SceneSpec::to_ron)), so that comments and layout do not count.
pub fn content_hash(scene: &Scene) -> u64 {
    crate::sweep::fnv1a64(scene.spec().to_ron().as_bytes())
}

impl SceneRecord {
    /// The record of `scene`, loaded from `given` (a path or a built-in
    /// name, as [`Scene::resolve`] reads it).
    pub fn new(scene: &Scene, given: &str) -> SceneRecord {
        let p = std::path::Path::new(given);
        let path = if p.exists() {
            std::fs::canonicalize(p)
                .unwrap_or_else(|_| p.to_path_buf())
                .display()
                .to_string()
        } else {
            format!("builtin:{given}")
        };
        SceneRecord {
            name: scene.spec().name.clone(),
            path,
            content_hash: format!("{:016x}", content_hash(scene)),
            effect_grid: scene.effect_grid(),
        }
    }

    /// The scene this record names, if it can still be read and its
    /// content is the one recorded (the same [`content_hash`]).
    pub fn scene(&self) -> Option<Scene> {
        let scene = match self.path.strip_prefix("builtin:") {
            Some(name) => Scene::builtin(name)?,
            None => Scene::load(&self.path).ok()?,
        };
        (format!("{:016x}", content_hash(&scene)) == self.content_hash).then_some(scene)
    }

    /// Checks a record read back from a file: a valid effect grid (at
    /// least one cell, at most [`MAX_EFFECTS`](crate::effect::MAX_EFFECTS),
    /// finite bounds).
    pub fn check(&self) -> Result<(), String> {
        self.effect_grid
            .validate()
            .map_err(|e| format!("its effect grid is not valid: {e}"))
    }
}

/// The largest `summary.json` `e3d report` reads (64 MiB; one holds a
/// few kB, plus about 25 bytes an effect).
pub const MAX_SUMMARY_JSON_BYTES: u64 = 64 << 20;
