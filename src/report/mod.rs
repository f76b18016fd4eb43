//! Figures.

pub mod scene_svg;
