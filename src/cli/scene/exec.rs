//! `e3d scene exec`: commands executed as they come, their outcomes as CSV.

use super::simulate::{calibration, say_cost, seconds_text, steps_text, world_error};
use crate::cli::console::{errln, write_stdout};
use crate::cli::{progress, CliError, CliResult};
use e3d::command::{CommandError, CommandSpace};
use e3d::scene::physics::DrawKey;
use e3d::scene::{Scene, WorldSpec};
use e3d::session::{reevaluate_with, run_key};
use e3d::world::{PhysicsScene, PhysicsWorld};
use e3d::{Command, OutcomeTable, World, WorldError};
use std::fmt::Write as _;
use std::path::Path;
use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::Mutex;

/// A command read by [`read_commands`], or why the input ends there.
pub(super) type Read<T = Command> = Result<T, CliError>;

/// Parses the `commands` of `e3d scene exec` in order with `parse` (`-`:
/// every non-blank line of stdin, as it comes) and sends them to `tx`, up
/// to the first that does not parse (sent as an error naming its stdin
/// line) or until the receiver is gone.
fn read_commands<T, E: std::fmt::Display>(
    parse: impl Fn(&str) -> Result<T, E>,
    commands: &[String],
    tx: &SyncSender<Read<T>>,
) {
    let send = |r: Read<T>| {
        let stop = r.is_err();
        tx.send(r).is_ok() && !stop
    };
    for arg in commands {
        if arg != "-" {
            if !send(parse(arg).map_err(CliError::input)) {
                return;
            }
            continue;
        }
        // one line at a time, each at most MAX_LINE_BYTES in memory
        // (standard input without a line feed, such as /dev/zero, is never
        // read whole)
        let stdin = std::io::stdin().lock();
        for (k, line) in e3d::text::bounded_lines(stdin, e3d::text::MAX_LINE_BYTES).enumerate() {
            let r = match line {
                Ok(l) if l.trim().is_empty() => continue,
                Ok(l) => parse(l.trim()).map_err(|e| e.to_string()),
                Err(e) => Err(e.to_string()),
            };
            if !send(r.map_err(|e| CliError::input(format!("stdin line {}: {e}", k + 1)))) {
                return;
            }
        }
    }
}

/// Appends the CSV row `LEAD,effect,reward,x,y` of the outcome `o`.
pub(super) fn push_row(out: &mut String, lead: impl std::fmt::Display, o: &e3d::Outcome) {
    let [x, y] = o.point;
    let _ = writeln!(out, "{lead},{},{},{x},{y}", o.effect, o.reward);
}

/// A reader thread of the `commands` ([`read_commands`], by `parse`),
/// its channel holding `bound` of them; not joined: it may wait on stdin
/// when the output ends with an error.
pub(super) fn reader<T: Send + 'static, E: std::fmt::Display>(
    parse: impl Fn(&str) -> Result<T, E> + Send + 'static,
    commands: Vec<String>,
    bound: usize,
) -> Receiver<Read<T>> {
    let (tx, rx) = std::sync::mpsc::sync_channel(bound);
    std::thread::spawn(move || read_commands(parse, &commands, &tx));
    rx
}

/// The parser of the commands of `space`.
fn symbols(space: &CommandSpace) -> impl Fn(&str) -> Result<Command, CommandError> + Send {
    let space = space.clone();
    move |text| space.parse(text)
}

/// `e3d scene exec --trace FILE`: each command's motion, one after the
/// other on one world, its CSV row printed as it is done and its frames
/// streamed into a temporary file renamed to FILE at the end (whole or not
/// at all).
pub(super) fn exec_trace(
    scene: &Scene,
    commands: Vec<String>,
    path: &Path,
    seed: u64,
) -> CliResult {
    let (Some(mut world), WorldSpec::Physics(spec)) = (scene.physics_world(), &scene.spec().world)
    else {
        return Err(CliError::input(format!(
            "scene `{}` is a grid: it has no motion to trace (`e3d scene render --command` draws a command's path)",
            scene.spec().name
        )));
    };
    let space = scene.command_space();
    // how many commands, unless stdin is read
    let known = (!commands.iter().any(|c| c == "-")).then_some(commands.len() as u64);
    let rx = reader(symbols(&space), commands, 64);
    let out_err = |e| crate::cli::cannot_write(path, e);
    // created exclusively: never through a link planted under its name
    // (a stream, such as /dev/stdout, is written through)
    let (tmp, f) = e3d::io::create_output(path).map_err(out_err)?;
    let mut file = std::io::BufWriter::new(f);
    let written = (|| -> CliResult {
        let mut first = true;
        let label = format!("scene exec {}", scene.spec().name);
        if let Some(n) = known {
            say_cost(&label, scene, n, 1, 1);
        }
        progress::track_stream(&label, "commands", |p| -> CliResult {
            if let Some(n) = known {
                p.set_total(n);
            }
            for (i, r) in rx.into_iter().enumerate() {
                let c = r?;
                let text = space.format(&c);
                // a noisy scene's draws: those of `scene exec`'s row
                world.set_draw_keys(&[run_key(seed, 0, i as u64)]);
                // frames go to the file as they are computed (a long
                // command's motion is never held whole)
                if first {
                    // a motion without frames writes the header
                    let header = e3d::world::Motion {
                        bodies: spec.bodies.iter().map(|b| b.name.clone()).collect(),
                        joints: spec.joints.iter().map(|j| j.name.clone()).collect(),
                        frames: Vec::new(),
                        outcome: e3d::Outcome {
                            effect: 0,
                            reward: 0.0,
                            point: [0.0; 2],
                        },
                    };
                    header
                        .write_csv(&mut file, Some(&text), true)
                        .map_err(out_err)?;
                }
                let mut written = Ok(());
                let m = world
                    .motion_each(&c, &mut |k, f| {
                        if written.is_ok() {
                            written =
                                e3d::world::Motion::write_csv_row(&mut file, Some(&text), k, &f);
                        }
                    })
                    .map_err(world_error)?;
                written.map_err(out_err)?;
                p.add(1);
                let mut row = String::new();
                if first {
                    row.push_str("command,effect,reward,x,y\n");
                }
                push_row(&mut row, &text, &m.outcome);
                write_stdout(row.as_bytes())?;
                first = false;
            }
            Ok(())
        })?;
        use std::io::Write as _;
        file.flush().map_err(out_err)
    })();
    drop(file);
    e3d::io::finish_output(tmp, path, written, out_err)
}

/// How `e3d scene exec` executes a chunk of commands; it keeps its worlds
/// from one chunk to the next (building a physics world costs).
pub(super) enum ExecPool<'a> {
    /// One world, one command after another: a grid, or a table look-up
    /// (microseconds a command).
    Direct(Box<dyn World + 'a>),
    /// A physics scene on every core: each piece of a chunk takes an idle
    /// world of `copies` copies (or builds one) and executes as a batch.
    Parallel {
        scene: PhysicsScene<'a>,
        copies: usize,
        idle: Mutex<Vec<PhysicsWorld>>,
    },
}

impl<'a> ExecPool<'a> {
    fn new(scene: &'a Scene, table: Option<OutcomeTable>) -> ExecPool<'a> {
        match (table, scene.as_physics()) {
            (Some(t), _) => ExecPool::Direct(Box::new(t)),
            (None, None) => ExecPool::Direct(scene.build()),
            (None, Some(physics)) => ExecPool::Parallel {
                scene: physics,
                // as the outcome table: bit-identical to one copy per world
                copies: e3d::world::table_copies(scene),
                idle: Mutex::new(Vec::new()),
            },
        }
    }

    /// Appends the result of each of `commands` to `out`, in order: those
    /// of [`World::execute`], bit for bit; with `memo`, the physics worlds'
    /// commands go through it ([`Memoized`](e3d::world::Memoized)).
    fn run(
        &mut self,
        commands: &[Command],
        keys: &[DrawKey],
        memo: Option<&e3d::world::OutcomeMemo>,
        out: &mut Vec<Result<e3d::Outcome, WorldError>>,
    ) {
        use rayon::prelude::*;
        match self {
            // a grid's move or a table's look-up costs less than the memo's
            ExecPool::Direct(world) => {
                world.set_draw_keys(keys);
                world.execute_batch(commands, out)
            }
            ExecPool::Parallel {
                scene,
                copies,
                idle,
            } => {
                // shared by the workers
                let idle: &Mutex<_> = idle;
                // every thread gets a piece, of at most one batch
                let piece = commands
                    .len()
                    .div_ceil(rayon::current_num_threads())
                    .clamp(1, *copies);
                let take = || crate::cli::locked(idle).pop();
                let pieces: Vec<Vec<_>> = commands
                    .par_chunks(piece)
                    .enumerate()
                    .map(|(k, part)| {
                        let mut world = take().unwrap_or_else(|| scene.world(*copies));
                        let mut results = Vec::with_capacity(part.len());
                        // each command's draws from its own key
                        world.set_draw_keys(
                            keys.get(k * piece..k * piece + part.len()).unwrap_or(&[]),
                        );
                        if let Some(m) = memo {
                            let mut through = e3d::world::Memoized::new(world, m);
                            through.execute_batch(part, &mut results);
                            world = through.into_inner();
                        } else {
                            world.execute_batch(part, &mut results);
                        }
                        crate::cli::locked(idle).push(world);
                        results
                    })
                    .collect();
                out.extend(pieces.into_iter().flatten());
            }
        }
    }
}

/// What the folder `dir` holds for `scene`: a whole table, or a memo of
/// the commands executed so far (empty, said why, when the file is missing
/// or cannot be used), whose new outcomes are written back at the end.
pub(super) fn exec_cache(
    scene: &Scene,
    dir: &Path,
) -> (Option<OutcomeTable>, Option<e3d::world::OutcomeMemo>) {
    use e3d::world::CachedOutcomes;
    let path = OutcomeTable::cache_path(scene, dir);
    match OutcomeTable::read_file(&path, scene) {
        Ok(CachedOutcomes::Full(t)) => (Some(t), None),
        Ok(CachedOutcomes::Partial(entries)) => {
            let m = new_memo(scene);
            if let Some(m) = &m {
                m.extend(entries);
            }
            (None, m)
        }
        Err(e) => {
            let shown = path.display().to_string();
            let why = if e.kind() == std::io::ErrorKind::NotFound {
                format!("no outcome table {shown} yet")
            } else if e.to_string().contains(&shown) {
                format!("cannot use the outcome table {e}")
            } else {
                format!("cannot use the outcome table {shown}: {e}")
            };
            errln!("note: {why}; simulating the commands, keeping their outcomes there");
            (None, new_memo(scene))
        }
    }
}

/// Without a table cache, a memo in memory for a scene with a mirror
/// symmetry: it hands a command its mirror's reflected outcome, which is
/// what the world gives it anyway, in half the rollouts.
fn mirror_memo(scene: &Scene) -> Option<e3d::world::OutcomeMemo> {
    match &scene.spec().world {
        WorldSpec::Physics(p) if p.symmetry.is_some() && p.active_noise().is_none() => {
            new_memo(scene)
        }
        _ => None,
    }
}

/// A memo of `scene`'s outcomes in memory, of the default cap.
fn new_memo(scene: &Scene) -> Option<e3d::world::OutcomeMemo> {
    let (space, effects) = (scene.command_space(), scene.num_effects());
    e3d::world::OutcomeMemo::new(&space, effects, e3d::world::DEFAULT_MEMO_CAP).ok()
}

/// `scene exec` on a scene with start contexts: `header`, then per command
/// the rows `rows` writes (one per start), printed as each is done.
fn exec_each(
    scene: &Scene,
    commands: Vec<String>,
    header: &str,
    mut rows: impl FnMut(&mut dyn e3d::world::Episodic, &Command, &mut String) -> CliResult,
) -> CliResult {
    let mut world = scene.build();
    let mut out = String::from(header);
    for read in reader(symbols(&scene.command_space()), commands, 1024) {
        rows(&mut *world, &read?, &mut out)?;
        write_stdout(out.as_bytes())?;
        out.clear();
    }
    Ok(())
}

/// `scene exec` on a grid with start contexts: every command from every
/// start cell of every context, one row each, with the context's name and
/// the start cell (a rectangle's every cell, in row order).
fn exec_contexts(scene: &Scene, grid: &e3d::scene::GridSpec, commands: Vec<String>) -> CliResult {
    let space = scene.command_space();
    let header = "context,start_row,start_col,command,effect,reward,x,y\n";
    exec_each(scene, commands, header, |world, c, out| {
        let command = space.format(c);
        for ctx in &grid.contexts {
            let ((r0, r1), (c0, c1)) = ctx.bounds();
            for r in r0..=r1 {
                for col in c0..=c1 {
                    let from = e3d::world::WorldState::Cell(r * grid.cols + col);
                    let (o, _) = world.execute_from(&from, c).map_err(world_error)?;
                    push_row(out, format_args!("{},{r},{col},{command}", ctx.name), &o);
                }
            }
        }
        Ok(())
    })
}

/// `scene exec` on a physics scene with start contexts: every command from
/// every context's start, one row each, with the context's name; a drawn
/// context's start is drawn with seed 0 (the same start on every row). A
/// noisy scene draws the `i`-th command's noise from [`run_key`]`(seed, 0,
/// i)` from every context (the same draws).
fn exec_physics_contexts(
    scene: &Scene,
    names: &[String],
    commands: Vec<String>,
    seed: u64,
) -> CliResult {
    use rand::SeedableRng;
    let (space, header) = (scene.command_space(), "context,command,effect,reward,x,y\n");
    let mut i = 0;
    exec_each(scene, commands, header, |world, c, out| {
        let key = run_key(seed, 0, i);
        i += 1;
        for (k, name) in names.iter().enumerate() {
            let mut rng = e3d::SessionRng::seed_from_u64(0);
            let from = world.draw_start(k, &mut rng).map_err(world_error)?;
            world.set_draw_keys(&[key]);
            let o = world.execute_outcome_from(&from, c).map_err(world_error)?;
            push_row(out, format_args!("{name},{}", space.format(c)), &o);
        }
        Ok(())
    })
}

/// Fills `chunk` with the commands read next: the first one waited for,
/// then those already read, up to `limit`. `None` when the reader is done
/// (nothing read); else `Some` of the error that ends the input, if one
/// came (the commands before it are in `chunk`).
fn next_chunk(
    rx: &Receiver<Read>,
    limit: usize,
    chunk: &mut Vec<Command>,
) -> Option<Option<CliError>> {
    chunk.clear();
    let mut next = rx.recv().ok()?;
    loop {
        match next {
            Ok(c) => chunk.push(c),
            Err(e) => return Some(Some(e)),
        }
        if chunk.len() == limit {
            return Some(None);
        }
        match rx.try_recv() {
            Ok(r) => next = r,
            Err(_) => return Some(None),
        }
    }
}

/// What the commands of `scene exec` cost, said once: before they run
/// when their number is known, else once those read so far reach
/// [`progress::LONG`] (stdin); never when a table looks them up.
struct CostNote {
    said: bool,
    /// Seconds a command takes by the calibrated cost model.
    per_command: f64,
    threads: usize,
    executed: u64,
}

impl CostNote {
    /// Says the cost of `known` commands now if their number is known.
    fn new(label: &str, scene: &Scene, known: Option<u64>, looked_up: bool) -> CostNote {
        let threads = rayon::current_num_threads();
        let copies = e3d::world::table_copies(scene);
        let said = looked_up || known.is_some_and(|n| say_cost(label, scene, n, threads, copies));
        let per_command = if said {
            0.0
        } else {
            e3d::world::batch_rollout_seconds(scene, copies) * calibration(scene, threads, copies)
        };
        CostNote {
            said,
            per_command,
            threads,
            executed: 0,
        }
    }

    /// Counts `n` more commands executed; says the cost once they are long.
    fn add(&mut self, n: u64, label: &str, scene: &Scene, p: &progress::Progress) {
        self.executed += n;
        let (executed, threads) = (self.executed, self.threads);
        if !self.said && executed as f64 * self.per_command / threads as f64 >= progress::LONG {
            self.said = true;
            let (steps, each) = (steps_text(scene), seconds_text(self.per_command));
            p.say(format!("{label}: {executed} commands so far{steps}, about {each} each on {threads} thread(s) by the cost model, calibrated here; more as stdin gives them"));
        }
    }
}

/// `e3d scene exec`: a reader thread parses the commands as they come; the
/// main thread waits for one, takes what else is queued (up to two
/// batches per thread), executes that chunk on every core and prints its rows
/// in input order, flushed, before the next chunk. The first command that
/// does not parse or that blows up ends the output, after the rows before
/// it, with its error. A noisy scene draws command `i`'s noise from
/// [`run_key`]`(seed, 0, i)`; with `repeat` R > 1, each command runs R
/// times (run `r` keyed `run_key(seed, r, i)`) and its row is its modal
/// effect and the share of the runs that end there.
pub(super) fn exec(
    scene: &Scene,
    commands: Vec<String>,
    table_cache: Option<&Path>,
    (repeat, seed): (u32, u64),
) -> CliResult {
    let contexts = e3d::world::start_contexts(scene).len();
    let noisy = match &scene.spec().world {
        WorldSpec::Physics(p) => p.active_noise().is_some(),
        WorldSpec::Grid(_) => false,
    };
    if let (Some(dir), true) = (table_cache, noisy) {
        let why = e3d::scene::physics::noise_refusal(&scene.spec().name, "a table cache");
        return Err(CliError::input(format!(
            "--table-cache {}: {why}",
            dir.display()
        )));
    }
    if repeat > 1 && contexts > 0 {
        return Err(CliError::input(format!(
            "--repeat: scene `{}` has start contexts, whose commands `scene exec` runs from each context's start; --repeat takes scenes without contexts",
            scene.spec().name
        )));
    }
    if let (Some(dir), true) = (table_cache, contexts > 0) {
        let (dir, name) = (dir.display(), &scene.spec().name);
        return Err(CliError::input(format!(
            "--table-cache {dir}: scene `{name}` has {contexts} start contexts, whose commands `scene exec` runs live from each context's start; it reads no table cache (drop --table-cache; `e3d scene table --cache DIR` builds the contexts' tables)"
        )));
    }
    match &scene.spec().world {
        WorldSpec::Grid(g) if !g.contexts.is_empty() => {
            return exec_contexts(scene, g, commands);
        }
        WorldSpec::Physics(p) if !p.contexts.is_empty() && scene.value_space().is_none() => {
            return exec_physics_contexts(scene, &p.context_names(), commands, seed);
        }
        _ => {}
    }
    let space = scene.command_space();
    let (table, memo) = match table_cache {
        Some(d) => exec_cache(scene, d),
        None => (None, mirror_memo(scene)),
    };
    let label = format!("scene exec {}", scene.spec().name);
    let known = (!commands.iter().any(|c| c == "-")).then_some(commands.len() as u64);
    let mut cost = CostNote::new(&label, scene, known, table.is_some());
    let mut executor = ExecPool::new(scene, table);
    // a noise-free command gives the same outcome every run: run it once
    let runs = if noisy { repeat as usize } else { 1 };
    // at most two batches of TABLE_COPIES per thread at once
    let limit = (2 * rayon::current_num_threads() * e3d::world::TABLE_COPIES / runs).max(1);
    let rx = reader(symbols(&space), commands, 2 * limit);
    let write = |text: &str| write_stdout(text.as_bytes());
    let header = if repeat > 1 {
        "command,effect,share,runs\n"
    } else {
        "command,effect,reward,x,y\n"
    };
    let (mut done, mut keys) = (0u64, Vec::<DrawKey>::new());
    let mut header_written = false;
    let (mut chunk, mut results, mut text) = (Vec::new(), Vec::new(), String::new());
    let mut end: Option<CliError> = None;
    progress::track_stream(&label, "commands", |p| -> CliResult {
        if let Some(n) = known {
            p.set_total(n);
        }
        while end.is_none() {
            match next_chunk(&rx, limit, &mut chunk) {
                None => break,
                Some(e) => end = e,
            }
            let first = done;
            done += chunk.len() as u64;
            p.add(chunk.len() as u64);
            cost.add((chunk.len() * runs) as u64, &label, scene, p);
            text.clear();
            if repeat > 1 {
                // the library's re-evaluation, on every core
                let each = reevaluate_with(&chunk, first, runs, seed, |cs, keys, out| {
                    executor.run(cs, keys, memo.as_ref(), out)
                });
                for (c, r) in chunk.iter().zip(each) {
                    match r {
                        Ok(r) => {
                            let (effect, share) = (r.effect, r.share());
                            let _ =
                                writeln!(text, "{},{effect},{share:.4},{repeat}", space.format(c));
                        }
                        Err(e) => {
                            end = Some(world_error(e));
                            break;
                        }
                    }
                }
            } else {
                results.clear();
                keys.clear();
                if noisy {
                    keys.extend((first..done).map(|i| run_key(seed, 0, i)));
                }
                executor.run(&chunk, &keys, memo.as_ref(), &mut results);
                // the rows up to the first failure, which ends the output
                for (c, r) in chunk.iter().zip(results.drain(..)) {
                    match r {
                        Ok(o) => push_row(&mut text, space.format(c), &o),
                        Err(e) => {
                            end = Some(world_error(e));
                            break;
                        }
                    }
                }
            }
            if !text.is_empty() {
                if !header_written {
                    text.insert_str(0, header);
                    header_written = true;
                }
                write(&text)?;
            }
        }
        Ok(())
    })?;
    // the new outcomes kept in the table folder (merged with its file); a
    // failure is a note, the output stands
    if let (Some(m), Some(dir)) = (memo.as_ref().filter(|m| !m.is_empty()), table_cache) {
        let path = OutcomeTable::cache_path(scene, dir);
        if let Err(e) = m.save(&path, scene) {
            errln!(
                "note: could not keep the outcomes in {}: {e}",
                path.display()
            );
        }
    }
    match end {
        Some(e) => Err(e),
        None if header_written => Ok(()),
        None => write(header),
    }
}
