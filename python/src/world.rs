//! `World`: executes a scene's commands, one or a batch, through an
//! outcome memo.

use crate::commands::{commands_from, values_from};
use crate::errors::Fail;
use crate::motion::motion_to_py;
use crate::outcome::{batch_to_py, outcome_to_py};
use crate::progress::{watched, Watch};
use crate::scene::PyScene;
use e3d::command::CommandSpace;
use e3d::scene::physics::DrawKey;
use e3d::scene::WorldSpec;
use e3d::world::PhysicsWorld;
use e3d::world::{table_copies, Memoized, OutcomeMemo, DEFAULT_MEMO_CAP};
use e3d::{Command, Outcome, World, WorldError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::Ordering;
use std::sync::Mutex;

/// Executes a scene's commands open loop from its start state; made by
/// `Scene.world()`.
///
/// Each world object keeps the outcome of every command it executed (an
/// outcome memo), so no command is simulated twice; `execute_batch` runs
/// the new commands of a batch in parallel on every core, many at once
/// per Rapier world where that is exact, without the GIL. The outcomes
/// are those of `e3d scene exec`, bit for bit.
#[pyclass(module = "e3d", name = "World", frozen)]
pub(crate) struct PyWorld {
    scene: PyScene,
    memo: OutcomeMemo,
    copies: usize,
    idle: Mutex<Vec<Box<dyn World + Send>>>,
    /// A single-copy Rapier world for `trace`, built on its first use.
    tracer: Mutex<Option<PhysicsWorld>>,
    /// A world of one copy for `execute` (one command: a world of many
    /// copies would step them all), built on its first use.
    single: Mutex<Option<Box<dyn World + Send>>>,
    /// Physics worlds of `copies` copies for a continuous scene's batches.
    valued: Mutex<Vec<PhysicsWorld>>,
    /// The most phase-end states the world of `execute` keeps (see
    /// `PhysicsWorld::set_prefix_states`).
    prefix_states: usize,
    /// The scene has a `noise` section: no memo, and command `i` of a
    /// call with seed `S` draws from `run_key(S, 0, i)` (as `e3d scene
    /// exec --seed S`).
    noisy: bool,
}

impl PyWorld {
    pub(crate) fn new(scene: PyScene, prefix_states: usize) -> PyWorld {
        let copies = table_copies(&scene.inner);
        // a space of more than 2^64 commands cannot be indexed: its memo
        // is refused, and such a world keeps nothing (cap 0 never fills)
        let memo = OutcomeMemo::new(&scene.space, scene.inner.num_effects(), DEFAULT_MEMO_CAP)
            .unwrap_or_else(|_| {
                let tiny = CommandSpace::repeat(1, &['0']).expect("valid");
                OutcomeMemo::new(&tiny, 1, 0).expect("small")
            });
        PyWorld {
            memo,
            copies,
            idle: Mutex::new(Vec::new()),
            tracer: Mutex::new(None),
            single: Mutex::new(None),
            valued: Mutex::new(Vec::new()),
            prefix_states,
            noisy: matches!(&scene.inner.spec().world, WorldSpec::Physics(p) if p.active_noise().is_some()),
            scene,
        }
    }

    /// The world of `execute`: one copy, keeping `prefix_states` states.
    fn build_single(&self) -> Box<dyn World + Send> {
        match self.scene.inner.physics_world() {
            Some(mut w) if self.scene.values.is_none() => {
                w.set_prefix_states(self.prefix_states);
                Box::new(w)
            }
            _ => self.scene.inner.build(),
        }
    }

    fn take(&self) -> Box<dyn World + Send> {
        let kept = self.idle.lock().unwrap_or_else(|e| e.into_inner()).pop();
        kept.unwrap_or_else(|| match self.scene.inner.as_physics() {
            Some(p) if self.copies > 1 => Box::new(p.world(self.copies)),
            _ => self.scene.inner.build(),
        })
    }

    fn give(&self, w: Box<dyn World + Send>) {
        self.idle.lock().unwrap_or_else(|e| e.into_inner()).push(w);
    }

    /// The outcome of one command, on a world of one copy (through the
    /// memo): the same outcome as in a batch, without stepping the copies
    /// a batch fills.
    /// Under noise it draws from `run_key(seed, 0, 0)`.
    fn run_one(&self, command: &Command, seed: u64) -> Result<Outcome, WorldError> {
        if self.noisy {
            let key = e3d::session::run_key(seed, 0, 0);
            return self
                .run_keyed(std::slice::from_ref(command), &[key], None)
                .remove(0);
        }
        let mut slot = self.single.lock().unwrap_or_else(|e| e.into_inner());
        let world = slot.take().unwrap_or_else(|| self.build_single());
        let (world, result) = self.through_memo(world, |w| w.execute(command));
        *slot = Some(world);
        result
    }

    /// Runs `f` on `world`, through the memo when the space has one.
    fn through_memo<R>(
        &self,
        world: Box<dyn World + Send>,
        f: impl FnOnce(&mut dyn World) -> R,
    ) -> (Box<dyn World + Send>, R) {
        if !self.memoised() {
            let mut w = world;
            let r = f(&mut *w);
            return (w, r);
        }
        let mut w = Memoized::new(world, &self.memo);
        let r = f(&mut w);
        (w.into_inner(), r)
    }

    /// Runs `f` on the single-copy physics world of `trace` (built on
    /// first use; a continuous scene is a physics scene).
    fn with_tracer<R>(&self, f: impl FnOnce(&mut PhysicsWorld) -> R) -> R {
        let mut slot = self.tracer.lock().unwrap_or_else(|e| e.into_inner());
        let physics = || self.scene.inner.physics_world().expect("a physics scene");
        f(slot.get_or_insert_with(physics))
    }

    /// The results of `items` run by `run` in parallel pieces of even
    /// size, at most `copies` each, so that no thread waits on another
    /// holding more; each piece adds its size to `watch`, and once the
    /// watch is cancelled the pieces not yet started fail (`Stopped`).
    fn in_pieces<T: Sync>(
        &self,
        items: &[T],
        watch: Option<&Watch>,
        run: impl Fn(&[T], &mut Vec<Result<Outcome, WorldError>>) + Sync,
    ) -> Vec<Result<Outcome, WorldError>> {
        let piece = items
            .len()
            .div_ceil(rayon::current_num_threads())
            .clamp(1, self.copies);
        let parts: Vec<Vec<Result<Outcome, WorldError>>> = items
            .par_chunks(piece)
            .map(|part| {
                if watch.is_some_and(Watch::cancelled) {
                    return vec![Err(WorldError::Stopped); part.len()];
                }
                let mut out = Vec::with_capacity(part.len());
                run(part, &mut out);
                if let Some(w) = watch {
                    w.add(part.len() as u64);
                }
                out
            })
            .collect();
        parts.into_iter().flatten().collect()
    }

    /// A physics world of `copies` copies for a continuous scene.
    fn take_valued(&self) -> PhysicsWorld {
        let kept = self.valued.lock().unwrap_or_else(|e| e.into_inner()).pop();
        let physics = || self.scene.inner.as_physics().expect("a physics scene");
        kept.unwrap_or_else(|| physics().world(self.copies))
    }

    /// The outcomes of continuous commands, in order (the first failure
    /// instead): in parallel pieces of at most `copies` commands, each
    /// stepped together on one world (as `e3d scene exec` does); one
    /// command runs on a world of one copy. Command `i` draws its noise
    /// from `run_key(seed, 0, i)`.
    fn run_values(
        &self,
        commands: &[Vec<f64>],
        watch: Option<&Watch>,
        seed: u64,
    ) -> Result<Vec<Outcome>, WorldError> {
        let keys: Vec<DrawKey> = (0..commands.len() as u64)
            .map(|i| e3d::session::run_key(seed, 0, i))
            .collect();
        self.run_values_keyed(commands, &keys, watch)
            .into_iter()
            .collect()
    }

    /// The result of each continuous command, command `k` drawing its
    /// noise from `keys[k]` ([`run_values`](Self::run_values)).
    fn run_values_keyed(
        &self,
        commands: &[Vec<f64>],
        keys: &[DrawKey],
        watch: Option<&Watch>,
    ) -> Vec<Result<Outcome, WorldError>> {
        if let ([one], [key]) = (commands, keys) {
            let r = self.with_tracer(|w| {
                w.set_draw_keys(&[*key]);
                w.execute_values(one)
            });
            if let Some(w) = watch {
                w.add(1);
            }
            return vec![r];
        }
        let pairs: Vec<(&Vec<f64>, DrawKey)> = commands.iter().zip(keys.iter().copied()).collect();
        self.in_pieces(&pairs, watch, |part, out| {
            let (vs, ks): (Vec<Vec<f64>>, Vec<DrawKey>) =
                part.iter().map(|&(v, k)| (v.clone(), k)).unzip();
            let mut w = self.take_valued();
            w.set_draw_keys(&ks);
            w.execute_values_batch(&vs, out);
            self.valued
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(w);
        })
    }

    fn memoised(&self) -> bool {
        self.scene.space.num_commands().is_some() && !self.noisy
    }

    /// The result of each of `commands`, command `k` drawing its noise
    /// from `keys[k]`: in parallel pieces, no memo.
    fn run_keyed(
        &self,
        commands: &[Command],
        keys: &[DrawKey],
        watch: Option<&Watch>,
    ) -> Vec<Result<Outcome, WorldError>> {
        let pairs: Vec<(&Command, DrawKey)> = commands.iter().zip(keys.iter().copied()).collect();
        self.in_pieces(&pairs, watch, |part, out| {
            let (cs, ks): (Vec<Command>, Vec<DrawKey>) =
                part.iter().map(|&(c, k)| (c.clone(), k)).unzip();
            let mut w = self.take();
            w.set_draw_keys(&ks);
            w.execute_batch(&cs, out);
            self.give(w);
        })
    }

    /// The outcome of each command, in order (the first failure, in input
    /// order, instead): each distinct command (a mirror-image pair counts
    /// once) looked up or simulated once, the new ones in parallel.
    ///
    /// With a `watch`, each piece adds its commands to `watch.done` (a
    /// repeated or known command counts as done at once), and once the
    /// watch is cancelled the pieces not yet started are skipped (the call
    /// fails).
    ///
    /// Under noise, command `i` draws from `run_key(seed, 0, i)`, no memo.
    fn run(
        &self,
        commands: &[Command],
        watch: Option<&Watch>,
        seed: u64,
    ) -> Result<Vec<Outcome>, WorldError> {
        if self.noisy {
            let keys: Vec<DrawKey> = (0..commands.len() as u64)
                .map(|i| e3d::session::run_key(seed, 0, i))
                .collect();
            return self.run_keyed(commands, &keys, watch).into_iter().collect();
        }
        let space = &self.scene.space;
        let keyer = self.take();
        // (index of the distinct command, whether it is the mirror image)
        let mut slot: Vec<(usize, bool)> = Vec::with_capacity(commands.len());
        let mut unique: Vec<Command> = Vec::new();
        // the distinct commands the memo does not know yet, by index
        let mut new = Vec::new();
        if self.memoised() {
            let mut first: HashMap<u64, usize> = HashMap::new();
            for c in commands {
                let own = space.index_of(c);
                let key = keyer.mirror_of(c).map_or(own, |m| space.index_of(&m));
                let k = *first.entry(key).or_insert_with(|| {
                    unique.push(c.clone());
                    if self.memo.peek(key).is_none() {
                        new.push(unique.len() - 1);
                    }
                    unique.len() - 1
                });
                slot.push((k, space.index_of(&unique[k]) != own));
            }
        } else {
            unique = commands.to_vec();
            new.extend(0..unique.len());
            slot.extend((0..commands.len()).map(|k| (k, false)));
        }
        if let Some(w) = watch {
            let done = commands.len() - new.len();
            w.base.store(done as u64, Ordering::Relaxed);
        }
        let (results, keyer) = self.outcomes(&unique, &new, keyer, watch);
        let mut out = Vec::with_capacity(commands.len());
        for (c, &(k, mirrored)) in commands.iter().zip(&slot) {
            match &results[k] {
                Ok(o) if mirrored => out.push(keyer.mirror_outcome(*o)),
                Ok(o) => out.push(*o),
                // the error as the world words it for this very command
                Err(e) if mirrored => {
                    let mut w = self.take();
                    let r = w.execute(c);
                    self.give(w);
                    return Err(r.err().unwrap_or_else(|| e.clone()));
                }
                Err(e) => return Err(e.clone()),
            }
        }
        self.give(keyer);
        Ok(out)
    }

    /// The result of each of `unique`: those of `new` (indices into
    /// `unique`, the commands the memo did not know) simulated in parallel
    /// pieces of even size, so that no thread waits on another holding
    /// more new commands (a lone new command on the world of `execute`);
    /// the others looked up in the memo on this thread, through `keyer`
    /// (returned).
    fn outcomes(
        &self,
        unique: &[Command],
        new: &[usize],
        mut keyer: Box<dyn World + Send>,
        watch: Option<&Watch>,
    ) -> (Vec<Result<Outcome, WorldError>>, Box<dyn World + Send>) {
        let simulated = if let [k] = new {
            // one new command: the world of `execute` (one copy, keeping
            // prefix states) runs it fastest, with the same bits
            let r = self.run_one(&unique[*k], 0);
            if let Some(w) = watch {
                w.add(1);
            }
            vec![r]
        } else {
            let simulated: Vec<Command> = new.iter().map(|&k| unique[k].clone()).collect();
            self.in_pieces(&simulated, watch, |part, out| {
                let (w, ()) = self.through_memo(self.take(), |w| w.execute_batch(part, out));
                self.give(w);
            })
        };
        let mut results: Vec<Option<Result<Outcome, WorldError>>> = vec![None; unique.len()];
        for (&k, r) in new.iter().zip(simulated) {
            results[k] = Some(r);
        }
        let known: Vec<usize> = (0..unique.len())
            .filter(|&k| results[k].is_none())
            .collect();
        if !known.is_empty() {
            let commands: Vec<Command> = known.iter().map(|&k| unique[k].clone()).collect();
            let mut w = Memoized::new(keyer, &self.memo);
            let mut out = Vec::with_capacity(commands.len());
            w.execute_batch(&commands, &mut out);
            keyer = w.into_inner();
            for (&k, r) in known.iter().zip(out) {
                results[k] = Some(r);
            }
        }
        let results = results
            .into_iter()
            .map(|r| r.expect("every command has a result"));
        (results.collect(), keyer)
    }
}

#[pymethods]
impl PyWorld {
    /// The scene.
    #[getter]
    fn scene(&self) -> PyScene {
        self.scene.clone()
    }

    /// Executes one command (a string of symbols, or an array of `slots`
    /// symbol indices) and returns its `Outcome`. On a scene with a
    /// `noise` section it draws its noise from `run_key(seed, 0, 0)`: the
    /// first row of `e3d scene exec --seed SEED`.
    #[pyo3(signature = (command, seed = 0))]
    fn execute(
        &self,
        py: Python<'_>,
        command: &Bound<'_, PyAny>,
        seed: u64,
    ) -> PyResult<Py<PyAny>> {
        let o = match &self.scene.values {
            Some(space) => {
                let vs = values_from(py, space, command, 1)?;
                py.detach(|| self.run_values(&vs, None, seed))
                    .map_err(Fail::from)?[0]
            }
            None => {
                let cs = commands_from(py, &self.scene.space, command, 1)?;
                py.detach(|| self.run_one(&cs[0], seed))
                    .map_err(Fail::from)?
            }
        };
        outcome_to_py(py, &o)
    }

    /// Executes a batch of commands, an integer array `[N, slots]` of
    /// symbol indices (uint8, as `Scene.parse` returns; other integer
    /// dtypes are converted) or a list of command strings, and returns a
    /// `BatchOutcome` of numpy arrays, one entry per row. Releases the GIL.
    /// `progress`: a callable, called as `progress(commands_done, N)` at
    /// most ten times a second and once at the end. Ctrl-C stops the batch
    /// and raises `KeyboardInterrupt` (the outcomes simulated so far are
    /// kept). On a scene with a `noise` section, row `i` draws its noise
    /// from `run_key(seed, 0, i)`: the rows of `e3d scene exec --seed
    /// SEED`.
    #[pyo3(signature = (commands, progress = None, seed = 0))]
    fn execute_batch(
        &self,
        py: Python<'_>,
        commands: &Bound<'_, PyAny>,
        progress: Option<&Bound<'_, PyAny>>,
        seed: u64,
    ) -> PyResult<Py<PyAny>> {
        if let Some(space) = &self.scene.values {
            let vs = values_from(py, space, commands, 2)?;
            let watch = Watch::default();
            let out = watched(py, progress, vs.len() as u64, &watch, |w| {
                self.run_values(&vs, Some(w), seed)
            })?
            .map_err(Fail::from)?;
            return batch_to_py(py, &out);
        }
        let cs = commands_from(py, &self.scene.space, commands, 2)?;
        // a small batch is not worth a thread of its own (a memo hit costs
        // less than starting one)
        let out = if progress.is_none() && cs.len() <= 256 {
            py.detach(|| self.run(&cs, None, seed))
        } else {
            let watch = Watch::default();
            watched(py, progress, cs.len() as u64, &watch, |w| {
                self.run(&cs, Some(w), seed)
            })?
        }
        .map_err(Fail::from)?;
        batch_to_py(py, &out)
    }

    /// Runs each command (as `execute_batch` takes them) `repeat` times
    /// under the scene's `noise`, run `r` of command `i` drawing from
    /// `run_key(seed, r, i)` (`e3d scene exec --repeat R --seed S`), and
    /// returns a dict: `effect` (each command's modal effect, ties to the
    /// lowest), `share` (the share of its runs ending there) and `runs`.
    /// A noise-free scene runs each command once (share 1). Symbols or
    /// values (a continuous scene's commands, as `execute_batch` takes
    /// them).
    #[pyo3(signature = (commands, repeat = 20, seed = 0))]
    fn reevaluate(
        &self,
        py: Python<'_>,
        commands: &Bound<'_, PyAny>,
        repeat: usize,
        seed: u64,
    ) -> PyResult<Py<PyAny>> {
        if repeat == 0 {
            return Err(PyValueError::new_err(
                "repeat: expected at least 1, found 0",
            ));
        }
        let runs = if self.noisy { repeat } else { 1 };
        let each = match &self.scene.values {
            Some(space) => {
                let vs = values_from(py, space, commands, 2)?;
                py.detach(|| {
                    e3d::session::reevaluate_with(&vs, 0, runs, seed, |vs, keys, out| {
                        out.extend(self.run_values_keyed(vs, keys, None))
                    })
                })
            }
            None => {
                let cs = commands_from(py, &self.scene.space, commands, 2)?;
                py.detach(|| {
                    e3d::session::reevaluate_with(&cs, 0, runs, seed, |cs, keys, out| {
                        out.extend(self.run_keyed(cs, keys, None))
                    })
                })
            }
        };
        let each = (each.into_iter())
            .collect::<Result<Vec<_>, _>>()
            .map_err(Fail::from)?;
        let d = pyo3::types::PyDict::new(py);
        let effect: Vec<u64> = each.iter().map(|r| r.effect as u64).collect();
        let share: Vec<f64> = each.iter().map(|r| r.share()).collect();
        d.set_item("effect", numpy::PyArray1::from_vec(py, effect))?;
        d.set_item("share", numpy::PyArray1::from_vec(py, share))?;
        d.set_item("runs", repeat)?;
        Ok(d.into_any().unbind())
    }

    /// The reproducibility of `learner`'s repertoire on this scene: the
    /// share of `commands` commands drawn from its current policy whose
    /// effect holds in at least 90% of `repeat` noisy runs
    /// (`e3d::session::reproducibility`, seeded `seed`; what `e3d run`
    /// reports with the session's seed). 1.0 on a noise-free scene; `None`
    /// for a learner whose policy cannot be drawn from. Scenes of symbols.
    #[pyo3(signature = (learner, repeat = 20, commands = 64, seed = 0))]
    fn reproducibility(
        &self,
        py: Python<'_>,
        learner: &Bound<'_, crate::saved::PyLearnerState>,
        repeat: usize,
        commands: usize,
        seed: u64,
    ) -> PyResult<Option<f64>> {
        if repeat == 0 || commands == 0 {
            return Err(PyValueError::new_err(format!(
                "repeat and commands: expected at least 1, found {repeat} and {commands}"
            )));
        }
        let state = learner.borrow();
        state.check_fits(&self.scene, None)?;
        let mut held = state.held.clone();
        drop(state);
        let options = e3d::session::RepeatOptions {
            commands,
            runs: repeat,
        };
        let r = py.detach(|| {
            let Some(l) = held.symbols() else {
                return Ok(None);
            };
            let mut w = self.take();
            let r = e3d::session::reproducibility(&mut *w, &*l, options, seed);
            self.give(w);
            r
        });
        Ok(r.map_err(Fail::from)?.map(|r| r.share))
    }

    /// The whole motion of one command (a string, or an array of `slots`
    /// symbol indices) on a physics scene, as a `Motion`: the time, every
    /// body's pose and velocity, every joint's angle and angular velocity,
    /// at the start and after every step. The numbers of
    /// `e3d scene exec SCENE COMMAND --trace FILE.csv`. A grid scene raises
    /// `ValueError` (it has no motion).
    fn trace(&self, py: Python<'_>, command: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let inner = &self.scene.inner;
        if matches!(inner.spec().world, WorldSpec::Grid(_)) {
            return Err(PyValueError::new_err(format!(
                "scene `{}` is a grid: it has no motion to trace (`e3d scene render --command` draws a command's path)",
                inner.spec().name
            )));
        }
        let (text, motion) = match &self.scene.values {
            Some(space) => {
                let v = values_from(py, space, command, 1)?.remove(0);
                let motion = py.detach(|| self.with_tracer(|w| w.motion_values(&v)));
                (space.format(&v), motion)
            }
            None => {
                let c = commands_from(py, &self.scene.space, command, 1)?.remove(0);
                let motion = py.detach(|| self.with_tracer(|w| w.motion(&c)));
                (self.scene.space.format(&c), motion)
            }
        };
        motion_to_py(py, text, motion.map_err(Fail::from)?)
    }

    /// Pickling: the scene's world (`scene.world(prefix_states)`); the
    /// outcomes and prefix states kept are not carried (they are simulated
    /// again when asked).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (usize,))> {
        let scene = Bound::new(py, self.scene.clone())?;
        Ok((scene.getattr("world")?, (self.prefix_states,)))
    }

    /// The most phase-end states `execute` keeps (`Scene.world`'s
    /// `prefix_states`).
    #[getter]
    fn prefix_states(&self) -> usize {
        self.prefix_states
    }

    /// How many commands' outcomes this world keeps (each simulated once).
    #[getter]
    fn memo_len(&self) -> usize {
        self.memo.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "World({:?}, {} outcomes kept)",
            self.scene.inner.spec().name,
            self.memo.len()
        )
    }
}
