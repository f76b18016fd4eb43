//! The scene tools on a scene of continuous commands: `exec` and
//! `render --command` of values.

use crate::cli::console::{outln, write_stdout};
use crate::cli::output::write_file;
use crate::cli::{CliError, CliResult};
use e3d::world::ContinuousScene;

/// `e3d scene exec` of continuous commands: `"values",effect,reward,x,y`
/// rows as each command is done; with `trace`, every command's motion in
/// that file (whole or absent).
pub(super) fn exec(
    scene: ContinuousScene,
    commands: &[String],
    trace: Option<&std::path::Path>,
) -> CliResult {
    use std::io::Write;
    let space = scene.values();
    let mut world = scene.physics().world(1);
    let mut file = match trace {
        Some(p) => {
            let (tmp, f) =
                e3d::io::create_temp_beside(p).map_err(|e| crate::cli::cannot_write(p, e))?;
            Some((p, tmp, std::io::BufWriter::new(f)))
        }
        None => None,
    };
    let result = (|| -> CliResult {
        let mut first = true;
        let parse = {
            let space = space.clone();
            move |text: &str| space.parse(text)
        };
        for v in super::exec::reader(parse, commands.to_vec(), 64) {
            let v = v?;
            let text = space.format(&v);
            let o = match &mut file {
                None => world.execute_values(&v),
                Some((p, _, f)) => world.motion_values(&v).and_then(|m| {
                    m.write_csv(&mut *f, Some(&format!("\"{text}\"")), first)
                        .map_err(|e| {
                            e3d::WorldError::Other(format!("{}: cannot write: {e}", p.display()))
                        })?;
                    Ok(m.outcome)
                }),
            }
            .map_err(|e| match e {
                e3d::WorldError::BadCommand { .. } => CliError::input(e),
                e3d::WorldError::Other(_) => CliError::output(e),
                _ => CliError::simulation(e),
            })?;
            let mut row = String::new();
            if first {
                row.push_str("values,effect,reward,x,y\n");
                first = false;
            }
            super::exec::push_row(&mut row, format_args!("\"{text}\""), &o);
            write_stdout(row.as_bytes())?;
        }
        if first {
            write_stdout(b"values,effect,reward,x,y\n")?;
        }
        if let Some((p, tmp, f)) = &mut file {
            let p: &std::path::Path = p;
            f.flush()
                .and_then(|()| std::fs::rename(&*tmp, p))
                .map_err(|e| crate::cli::cannot_write(p, e))?;
        }
        Ok(())
    })();
    if let (Err(_), Some((_, tmp, _))) = (&result, &file) {
        let _ = std::fs::remove_file(tmp);
    }
    result
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
