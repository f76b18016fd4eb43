//! The library: learners, sessions, outcome tables, scenes and sweeps in
//! code, the scene and sweep loaders, slot templates, effect binnings,
//! the baselines, import circles, and the report pages. One test
//! binary; each module is one topic.

#[path = "../common/mod.rs"]
mod common;

mod bad_scenes;
mod baselines;
mod build_script;
mod consistency;
mod contexts;
mod drives;
mod edge_cases;
mod effects;
mod every_scene;
mod faults;
mod fuzz_outputs;
mod fuzz_scenes;
mod fuzz_sweeps;
mod grid;
mod imports;
mod intervals;
mod learner_states;
mod learners;
mod motion_svg;
mod outcomes;
mod paper;
mod quality_diversity;
mod reference;
mod report_html;
mod scene_api;
mod scene_axes;
mod shorthand;
mod slot_templates;
mod sweep_open;
mod targets;
mod thresholds;
