//! The `e3d` command line, run as a program: outputs, refusals, exit codes,
//! the scene tools, sweeps and the pages in a browser. One test binary;
//! each module is one topic.

#[path = "../common/mod.rs"]
mod common;

mod check_samples;
mod chromium;
mod commands;
mod compare;
mod console_escapes;
mod context_tools;
mod contexts;
mod faults;
mod mjcf;
mod noise;
mod output_paths;
mod own_outputs;
mod scene_check;
mod scene_commands;
mod scene_exec;
mod scene_pictures;
mod sweep;
mod sweep_axes;
mod sweep_continuous;
mod sweep_failures;
mod table_cache;
mod temporary_files;
