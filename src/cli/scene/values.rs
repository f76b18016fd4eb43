//! The scene tools on a scene of continuous commands: `exec` and
//! `render --command` of values.

use crate::cli::console::{outln, write_stdout};
use crate::cli::output::write_file;
use crate::cli::{cannot_write, CliError, CliResult};
use e3d::session::{reevaluate_with, run_key};
use e3d::world::ContinuousScene;
use e3d::WorldError;
use std::fmt::Write as _;
use std::path::Path;

/// `e3d scene exec` of continuous commands: `"values",effect,reward,x,y`
/// rows as each command is done; with `trace`, every command's motion in
/// that file (whole or absent). A noisy scene draws the `i`-th command's
/// noise from [`run_key`]`(seed, 0, i)`; with `repeat` R > 1, each command
/// runs R times (run `r` keyed `run_key(seed, r, i)`, the library's
/// [`reevaluate_with`]) and its row is `"values",effect,share,runs`.
pub(super) fn exec(
    scene: ContinuousScene,
    commands: &[String],
    trace: Option<&Path>,
    (repeat, seed): (u32, u64),
) -> CliResult {
    use e3d::World as _;
    use std::io::Write;
    let space = scene.values();
    let mut world = scene.physics().world(1);
    let noisy = !world.is_deterministic();
    if repeat > 1 {
        return exec_repeated(&mut world, space, commands, (repeat, seed), noisy);
    }
    let mut file = match trace {
        Some(p) => {
            let (tmp, f) = e3d::io::create_temp_beside(p).map_err(|e| cannot_write(p, e))?;
            Some((p, tmp, std::io::BufWriter::new(f)))
        }
        None => None,
    };
    let failed = |e: WorldError| match e {
        WorldError::BadCommand { .. } => CliError::input(e),
        WorldError::Other(_) => CliError::output(e),
        _ => CliError::simulation(e),
    };
    let written = (|| -> CliResult {
        let parse = {
            let space = space.clone();
            move |text: &str| space.parse(text)
        };
        let mut header = Some("values,effect,reward,x,y\n");
        for (i, v) in super::exec::reader(parse, commands.to_vec(), 64)
            .into_iter()
            .enumerate()
        {
            let v = v?;
            let text = format!("\"{}\"", space.format(&v));
            world.set_draw_keys(&[run_key(seed, 0, i as u64)]);
            let o = match &mut file {
                None => world.execute_values(&v).map_err(failed)?,
                Some((p, _, f)) => {
                    let m = world.motion_values(&v).map_err(failed)?;
                    let first = header.is_some();
                    m.write_csv(&mut *f, Some(&text), first)
                        .map_err(|e| cannot_write(p, e))?;
                    m.outcome
                }
            };
            let mut row = header.take().unwrap_or_default().to_string();
            super::exec::push_row(&mut row, &text, &o);
            write_stdout(row.as_bytes())?;
        }
        if let Some(h) = header {
            write_stdout(h.as_bytes())?;
        }
        match &mut file {
            Some((p, _, f)) => f.flush().map_err(|e| cannot_write(p, e)),
            None => Ok(()),
        }
    })();
    match file {
        Some((p, tmp, f)) => {
            drop(f);
            e3d::io::finish_output(Some(tmp), p, written, |e| cannot_write(p, e))
        }
        None => written,
    }
}

/// `e3d scene exec --repeat R` of continuous commands: per command, as
/// each is done, `"values",effect,share,runs` (one run on a noise-free
/// scene, share 1).
fn exec_repeated(
    world: &mut e3d::world::PhysicsWorld,
    space: &e3d::command::ValueSpace,
    commands: &[String],
    (repeat, seed): (u32, u64),
    noisy: bool,
) -> CliResult {
    use e3d::World as _;
    let runs = if noisy { repeat as usize } else { 1 };
    let parse = {
        let space = space.clone();
        move |text: &str| space.parse(text)
    };
    let mut header = Some("values,effect,share,runs\n");
    for (i, v) in super::exec::reader(parse, commands.to_vec(), 64)
        .into_iter()
        .enumerate()
    {
        let v = v?;
        let each = reevaluate_with(
            std::slice::from_ref(&v),
            i as u64,
            runs,
            seed,
            |cs, keys, out| {
                world.set_draw_keys(keys);
                world.execute_values_batch(cs, out)
            },
        );
        let r = each.into_iter().next().expect("one command");
        let r = r.map_err(super::simulate::world_error)?;
        let mut row = header.take().unwrap_or_default().to_string();
        let text = space.format(&v);
        let _ = writeln!(row, "\"{text}\",{},{:.4},{repeat}", r.effect, r.share());
        write_stdout(row.as_bytes())?;
    }
    if let Some(h) = header {
        write_stdout(h.as_bytes())?;
    }
    Ok(())
}

/// `e3d scene render --command VALUES [--animate]` of a continuous scene.
pub(super) fn render(
    scene: ContinuousScene,
    text: &str,
    animate: bool,
    out: &std::path::Path,
) -> CliResult {
    use e3d::report::motion_svg;
    let space = scene.values();
    let v = space.parse(text).map_err(CliError::input)?;
    let cmd = space.format(&v);
    let mut world = scene.physics().world(1);
    let page = if animate {
        let motion = world
            .motion_values(&v)
            .map_err(super::simulate::world_error)?;
        let svg = motion_svg::motion_svg(scene.scene(), &cmd, &motion)
            .map_err(|e| CliError::input(e.to_string()))?;
        super::render::animation_page(scene.scene(), &cmd, svg, out)
    } else {
        let overlay = super::render::traced(
            cmd,
            world
                .trace_values(&v)
                .map_err(super::simulate::world_error)?,
        );
        e3d::report::scene_svg::scene_svg(scene.scene(), Some(&overlay))
    };
    write_file(out, page.as_bytes())?;
    outln!("wrote {}", out.display());
    Ok(())
}
