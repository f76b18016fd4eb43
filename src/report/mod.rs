//! Figures.

pub mod sweep_plot;
