//! `e3d run` on a scene of continuous commands: live physics, one world
//! per session, sessions in parallel on every core.

use super::output::write_file;
use super::run::{join_trials, print_header, print_metrics, RunArgs};
use super::{CliError, CliResult};
use e3d::{run_value_sessions, Metrics, Params, Scene, SessionConfig, Target, ValueSessionRecord};
use serde::Serialize;

/// What `summary.json` holds for a run of continuous commands.
#[derive(Serialize)]
struct Summary<'a> {
    e3d_version: &'static str,
    scene: &'a str,
    learner: &'static str,
    #[serde(flatten)]
    params: Params,
    use_reward: bool,
    /// Always `"live"`: continuous commands have no table or memo.
    execution: &'static str,
    /// Per session: its seed, metrics, effect counts and final policy.
    sessions: Vec<OneSession<'a>>,
}

#[derive(Serialize)]
struct OneSession<'a> {
    seed: u64,
    #[serde(flatten)]
    metrics: &'a Metrics,
    effect_counts: Vec<f64>,
    /// Per slot: the mean and standard deviation of the final policy, in
    /// the slot's unit.
    final_policy: Vec<SlotPolicy>,
}

#[derive(Serialize)]
struct SlotPolicy {
    mean: f64,
    sd: f64,
}

/// Runs `a`'s sessions of continuous commands on `scene`.
pub fn run(a: &RunArgs, scene: &Scene, params: Params, seeds: &[u64]) -> CliResult {
    if a.table_cache.is_some() {
        return Err(CliError::input(format!(
            "--table-cache: scene `{}` takes continuous commands, which have no outcome table (every trial is simulated)",
            scene.name
        )));
    }
    if matches!(a.memo.outcomes.0, Some(s) if s != e3d::Strategy::Live) {
        return Err(CliError::input(format!(
            "--outcomes: scene `{}` takes continuous commands, which run live only (no table, no memo)",
            scene.name
        )));
    }
    let space = scene.value_space().expect("a continuous scene");
    let num_effects = scene.num_effects();
    let target = Target::Uniform;
    let make = || {
        a.learner
            .make_continuous(&params, &space, num_effects, &target)
            .map_err(CliError::input)
    };
    make()?;
    scene.try_physics_world().map_err(CliError::input)?;
    let configs: Vec<SessionConfig> = seeds
        .iter()
        .map(|&seed| SessionConfig {
            trials: a.trials as usize,
            seed,
            use_reward: !a.no_reward,
        })
        .collect();
    let sessions = seeds.len();
    let steps = scene.steps_per_command().unwrap_or(0) as u64;
    eprintln!(
        "outcomes: live: continuous commands, {} trials x {sessions} session(s) x {steps} steps, on {} thread(s)",
        a.trials,
        rayon::current_num_threads()
    );
    let label = format!("run {}", scene.name);
    let total = a.trials.saturating_mul(sessions as u64);
    let records = super::progress::track(&label, "trials", total, |p| {
        let add = |k: u64| p.add(k);
        run_value_sessions(
            || scene.physics_world().expect("validated above"),
            || make().expect("checked above"),
            &configs,
            &add,
        )
    })
    .map_err(CliError::simulation)?;
    let metrics: Vec<Metrics> = records.iter().map(|r| r.metrics(&target)).collect();
    print_header(a, &scene.name, " (continuous)", &params, seeds);
    print_metrics(&metrics, seeds, num_effects);
    if let Some(dir) = &a.out {
        write_out(dir, a, scene, params, seeds, &records, &metrics, &space)?;
    }
    Ok(())
}

/// Writes DIR/trials.csv (whole or absent) and DIR/summary.json.
#[allow(clippy::too_many_arguments)]
fn write_out(
    dir: &std::path::Path,
    a: &RunArgs,
    scene: &Scene,
    params: Params,
    seeds: &[u64],
    records: &[ValueSessionRecord],
    metrics: &[Metrics],
    space: &e3d::ValueSpace,
) -> CliResult {
    let several = records.len() > 1;
    let csv = dir.join("trials.csv");
    let (part, file) = e3d::io::create_temp_beside(&csv)
        .map_err(|e| CliError::output(format!("{}: cannot write: {e}", csv.display())))?;
    let written = (|| -> std::io::Result<()> {
        let mut out = std::io::BufWriter::new(file);
        for (i, r) in records.iter().enumerate() {
            r.write_trials_csv(space, several.then_some(i), false, &mut out)?;
        }
        std::io::Write::flush(&mut out)
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&part);
        return Err(CliError::output(format!(
            "{}: cannot write: {e}",
            csv.display()
        )));
    }
    let header = if several {
        "session,trial,values,effect,reward,x,y"
    } else {
        "trial,values,effect,reward,x,y"
    };
    join_trials(&csv, header, &[part])?;
    let summary = Summary {
        e3d_version: env!("CARGO_PKG_VERSION"),
        scene: &scene.name,
        learner: a.learner.as_str(),
        params,
        use_reward: !a.no_reward,
        execution: "live",
        sessions: records
            .iter()
            .zip(metrics)
            .zip(seeds)
            .map(|((r, m), &seed)| OneSession {
                seed,
                metrics: m,
                effect_counts: r.effect_counts(0..r.trials()),
                final_policy: r
                    .final_policy
                    .iter()
                    .map(|&(mean, sd)| SlotPolicy { mean, sd })
                    .collect(),
            })
            .collect(),
    };
    let mut json = serde_json::to_vec_pretty(&summary).map_err(CliError::output)?;
    json.push(b'\n');
    write_file(&dir.join("summary.json"), &json)?;
    println!(
        "wrote {} and {}",
        csv.display(),
        dir.join("summary.json").display()
    );
    Ok(())
}

/// `e3d scene ...` on a continuous scene: the sub-commands that differ
/// (`exec`, `render --command`) and those that cannot apply (`table`,
/// `reward-cell`, `stats`, which enumerate the commands); `None` for the
/// others, and for scenes of symbols or that do not load (the plain path
/// then reports them).
pub fn scene(cmd: &super::scene::SceneCmd) -> Option<CliResult> {
    use super::scene::SceneCmd as C;
    let name = match cmd {
        C::Exec { scene, .. }
        | C::Render { scene, .. }
        | C::RewardCell { scene, .. }
        | C::Table { scene, .. }
        | C::Stats { scene, .. } => scene,
        _ => return None,
    };
    let scene = Scene::resolve(name).ok().filter(Scene::is_continuous)?;
    let refuse = |what: &str| Some(scene.require_symbols(what).map_err(CliError::input));
    match cmd {
        C::Exec {
            commands,
            table_cache: None,
            trace,
            ..
        } => Some(exec(&scene, commands, trace.as_deref())),
        C::Exec { .. } => refuse("`e3d scene exec --table-cache` (an outcome table)"),
        C::Render {
            command: Some(text),
            animate,
            out,
            ..
        } => Some(render(&scene, text, *animate, out)),
        C::Render { .. } => None,
        C::RewardCell { .. } => refuse("`e3d scene reward-cell` (which executes every command)"),
        C::Table { .. } => refuse("`e3d scene table` (an outcome table)"),
        C::Stats { .. } => refuse("`e3d scene stats` (which executes every command)"),
        _ => None,
    }
}

/// The commands of `scene exec` (`-`: every non-blank line of stdin), each
/// parsed when it is reached; an error names its stdin line.
fn read_values<'a>(
    space: &'a e3d::ValueSpace,
    commands: &'a [String],
) -> impl Iterator<Item = Result<Vec<f64>, CliError>> + 'a {
    use std::io::BufRead;
    commands
        .iter()
        .flat_map(move |arg| -> Box<dyn Iterator<Item = _>> {
            if arg != "-" {
                return Box::new(std::iter::once(space.parse(arg).map_err(CliError::input)));
            }
            Box::new(
                std::io::stdin()
                    .lock()
                    .lines()
                    .enumerate()
                    .filter(|(_, l)| l.as_ref().map_or(true, |l| !l.trim().is_empty()))
                    .map(move |(k, l)| {
                        let at = |e: &dyn std::fmt::Display| {
                            CliError::input(format!("stdin line {}: {e}", k + 1))
                        };
                        l.map_err(|e| at(&e))
                            .and_then(|l| space.parse(&l).map_err(|e| at(&e)))
                    }),
            )
        })
}

/// `e3d scene exec` of continuous commands: `"values",effect,reward,x,y`
/// rows as each command is done; with `trace`, every command's motion in
/// that file (whole or absent).
fn exec(scene: &Scene, commands: &[String], trace: Option<&std::path::Path>) -> CliResult {
    use std::io::Write;
    let space = scene.value_space().expect("a continuous scene");
    let mut world = scene.physics_world().expect("a physics scene");
    let mut stdout = std::io::stdout().lock();
    let mut file = match trace {
        Some(p) => {
            let (tmp, f) = e3d::io::create_temp_beside(p)
                .map_err(|e| CliError::output(format!("{}: cannot write: {e}", p.display())))?;
            Some((p, tmp, std::io::BufWriter::new(f)))
        }
        None => None,
    };
    let result = (|| -> CliResult {
        let mut first = true;
        for v in read_values(&space, commands) {
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
            row.push_str(&format!(
                "\"{text}\",{},{},{},{}\n",
                o.effect, o.reward, o.point[0], o.point[1]
            ));
            stdout
                .write_all(row.as_bytes())
                .and_then(|()| stdout.flush())
                .map_err(|e| CliError::output(format!("standard output: {e}")))?;
        }
        if first {
            stdout
                .write_all(b"values,effect,reward,x,y\n")
                .map_err(|e| CliError::output(format!("standard output: {e}")))?;
        }
        if let Some((p, tmp, f)) = &mut file {
            let p: &std::path::Path = p;
            f.flush()
                .and_then(|()| std::fs::rename(&*tmp, p))
                .map_err(|e| CliError::output(format!("{}: cannot write: {e}", p.display())))?;
        }
        Ok(())
    })();
    if let (Err(_), Some((_, tmp, _))) = (&result, &file) {
        let _ = std::fs::remove_file(tmp);
    }
    result
}

/// `e3d scene render --command VALUES [--animate]` of a continuous scene.
fn render(scene: &Scene, text: &str, animate: bool, out: &std::path::Path) -> CliResult {
    use e3d::report::motion_svg;
    let space = scene.value_space().expect("a continuous scene");
    let v = space.parse(text).map_err(CliError::input)?;
    let cmd = space.format(&v);
    let mut world = scene.physics_world().expect("a physics scene");
    let bad = |e: e3d::WorldError| match e {
        e3d::WorldError::BadCommand { .. } => CliError::input(e),
        _ => CliError::simulation(e),
    };
    let page = if animate {
        let motion = world.motion_values(&v).map_err(bad)?;
        let svg = motion_svg::motion_svg(scene, &cmd, &motion)
            .map_err(|e| CliError::input(e.to_string()))?;
        let html = out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
        if html {
            motion_svg::html_page(&format!("{}: command {cmd}", scene.name), &svg)
        } else {
            svg
        }
    } else {
        let t = world.trace_values(&v).map_err(bad)?;
        let overlay = e3d::report::scene_svg::Overlay {
            command: cmd,
            points: t.points,
            poses: Some(t.poses),
            effect: t.outcome.effect,
            reward: t.outcome.reward,
        };
        e3d::report::scene_svg::scene_svg(scene, Some(&overlay))
    };
    write_file(out, page.as_bytes())?;
    println!("wrote {}", out.display());
    Ok(())
}
