//! `EpisodeWorld`: one episode at a time, command by command, stepped
//! from Python (the draws and executions of `run_episodes`).

use crate::commands::commands_from;
use crate::contextual::{commands_arg, observe_arg, observe_name};
use crate::errors::{int_arg, usize_arg, Fail};
use crate::outcome::outcome_to_py;
use crate::scene::{scene_of, PyScene};
use e3d::episode::Observe;
use e3d::world::{Episodic, WorldState};
use e3d::{SessionRng, World};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use rand::{RngExt, SeedableRng};
use std::sync::Mutex;

/// One episode at a time, command by command: what a closed loop runs
/// (`run_episodes`'s draws and executions), stepped from Python. Made by
/// `EpisodeWorld(scene, commands=K, observe=None, use_reward=True)`.
///
/// `reset(seed=None, start=None)` draws the episode's start context (one
/// integer of the generator, when the scene has several; `start` picks it
/// instead) and its start state, and returns the observed context;
/// `step(command)` executes the command from the current state and
/// returns `(context, outcome, done)`, the reward 0 but after the
/// episode's last command. `seed` reseeds the generator (the library's
/// `SessionRng`); without it the draws continue. `rng` (a `SessionRng`)
/// draws from that generator instead: the one a learner proposes from, so
/// that a loop draws what `run_episodes` draws, in its order.
#[pyclass(module = "e3d", name = "EpisodeWorld")]
pub(crate) struct PyEpisodeWorld {
    scene: PyScene,
    world: Mutex<Box<dyn Episodic + Send>>,
    rng: SessionRng,
    state: Option<WorldState>,
    /// Commands executed in this episode.
    done: usize,
    start: usize,
    #[pyo3(get)]
    commands: usize,
    observe: Observe,
    #[pyo3(get)]
    use_reward: bool,
    command: e3d::Command,
    /// The generator the start state was drawn from, as it was before
    /// the draw, and the commands executed since: what rebuilds the
    /// episode's state in a copy (a physics state's Rapier snapshot is
    /// not carried by pickling).
    before_start: Option<SessionRng>,
    history: Vec<Vec<u8>>,
}

/// What `EpisodeWorld` pickles besides its constructor's arguments: the
/// generator and where the episode stands.
#[derive(serde::Serialize, serde::Deserialize)]
struct Progress {
    rng: SessionRng,
    state: Option<WorldState>,
    done: usize,
    start: usize,
    #[serde(default)]
    before_start: Option<SessionRng>,
    #[serde(default)]
    history: Vec<Vec<u8>>,
}

impl PyEpisodeWorld {
    fn world(&self) -> std::sync::MutexGuard<'_, Box<dyn Episodic + Send>> {
        self.world.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The state after drawing the start from `rng` and executing
    /// `history` from it.
    fn replay(&self, mut rng: SessionRng, history: &[Vec<u8>]) -> PyResult<WorldState> {
        let mut world = self.world();
        let mut state = world.draw_start(self.start, &mut rng).map_err(Fail::from)?;
        for symbols in history {
            let c = e3d::Command::new(symbols.clone());
            e3d::world::check_command(world.command_space(), &c).map_err(Fail::from)?;
            state = world.execute_from(&state, &c).map_err(Fail::from)?.1;
        }
        Ok(state)
    }

    fn observed(&self, start: usize, effect: usize) -> usize {
        match self.observe {
            Observe::StartContext => start,
            Observe::State => effect,
            Observe::Blind => 0,
        }
    }
}

#[pymethods]
impl PyEpisodeWorld {
    #[new]
    #[pyo3(signature = (scene, commands = None, observe = None, use_reward = true, closed_loop = false))]
    fn new(
        scene: &Bound<'_, PyAny>,
        commands: Option<&Bound<'_, PyAny>>,
        observe: Option<&str>,
        use_reward: bool,
        closed_loop: bool,
    ) -> PyResult<Self> {
        let scene = scene_of(scene)?;
        scene.require_symbols("EpisodeWorld")?;
        let commands = commands.map(commands_arg).transpose()?.unwrap_or(1);
        let observe = observe_arg(observe, commands, closed_loop)?;
        let world = scene.inner.build();
        let command = world.command_space().first();
        Ok(PyEpisodeWorld {
            scene,
            world: Mutex::new(world),
            rng: SessionRng::seed_from_u64(0),
            state: None,
            done: 0,
            start: 0,
            commands,
            observe,
            use_reward,
            command,
            before_start: None,
            history: Vec::new(),
        })
    }

    /// What the learner observes: `"start"`, `"state"` or `"blind"`.
    #[getter]
    fn observe(&self) -> &'static str {
        observe_name(self.observe)
    }

    /// The number of contexts observed (`Discrete(num_contexts)`): the
    /// start contexts, the effects, or 1.
    #[getter]
    fn num_contexts(&self) -> usize {
        match self.observe {
            Observe::StartContext => self.world().num_contexts(),
            Observe::State => self.world().num_effects(),
            Observe::Blind => 1,
        }
    }

    /// The scene's start contexts (1 when it declares none).
    #[getter]
    fn num_starts(&self) -> usize {
        self.world().num_contexts()
    }

    /// The current episode's start context.
    #[getter]
    fn start(&self) -> usize {
        self.start
    }

    #[getter]
    fn scene(&self) -> PyScene {
        self.scene.clone()
    }

    #[pyo3(signature = (seed = None, start = None, rng = None))]
    fn reset(
        &mut self,
        seed: Option<&Bound<'_, PyAny>>,
        start: Option<&Bound<'_, PyAny>>,
        rng: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let seed = seed.filter(|s| !s.is_none());
        let rng = rng.filter(|r| !r.is_none());
        if seed.is_some() && rng.is_some() {
            return Err(PyValueError::new_err("give either seed or rng, not both"));
        }
        if let Some(s) = seed {
            self.rng = SessionRng::seed_from_u64(int_arg(s, "seed", 0)?);
        }
        // the caller's generator (the one its learner proposes from), as
        // run_episodes draws starts and commands from one
        let mut lent = None;
        let rng: &mut SessionRng = match rng {
            Some(r) => {
                let r = r
                    .cast::<crate::rng::PyRng>()
                    .map_err(|_| PyTypeError::new_err("rng: expected an e3d.SessionRng"))?;
                lent.insert(r.try_borrow_mut()?).lent()?
            }
            None => &mut self.rng,
        };
        let n = self
            .world
            .get_mut()
            .unwrap_or_else(|p| p.into_inner())
            .num_contexts();
        let start = match start.filter(|s| !s.is_none()) {
            Some(s) => {
                let s = usize_arg(s, "start", 0)?;
                if s >= n {
                    return Err(PyValueError::new_err(format!(
                        "start = {s}: expected a start context in [0, {n})"
                    )));
                }
                s
            }
            None if n > 1 => rng.random_range(0..n),
            None => 0,
        };
        let before_start = rng.clone();
        let world = self.world.get_mut().unwrap_or_else(|p| p.into_inner());
        let state = world.draw_start(start, rng).map_err(Fail::from)?;
        self.before_start = Some(before_start);
        self.history.clear();
        let effect = match self.observe {
            Observe::State => world.bin_state(&state).map_err(Fail::from)?,
            _ => 0,
        };
        self.state = Some(state);
        self.start = start;
        self.done = 0;
        Ok(self.observed(start, effect))
    }

    /// Executes `command` (symbols or text) from the current state:
    /// `(context, outcome, done)`.
    fn step(&mut self, command: &Bound<'_, PyAny>) -> PyResult<(usize, Py<PyAny>, bool)> {
        let Some(state) = self.state.as_ref() else {
            return Err(PyRuntimeError::new_err(
                "EpisodeWorld.step: the episode is over (or never started); call reset() first",
            ));
        };
        let parsed = commands_from(command.py(), &self.scene.space, command, 1)?;
        if parsed.len() != 1 {
            return Err(PyValueError::new_err(format!(
                "EpisodeWorld.step: expected one command, found {}",
                parsed.len()
            )));
        }
        self.command.symbols.clone_from(&parsed[0].symbols);
        let (mut out, next) = self
            .world()
            .execute_from(state, &self.command)
            .map_err(Fail::from)?;
        self.done += 1;
        self.history.push(self.command.symbols.clone());
        let last = self.done == self.commands;
        if !last || !self.use_reward {
            out.reward = 0.0;
        }
        self.state = (!last).then_some(next);
        let context = self.observed(self.start, out.effect);
        Ok((context, outcome_to_py(command.py(), &out)?, last))
    }

    /// Pickles as its scene, arguments, generator and the episode's state:
    /// a copy goes on with the same draws and outcomes.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(
        Bound<'py, PyAny>,
        (PyScene, usize, &'static str, bool),
        String,
    )> {
        let me = slf.borrow();
        let progress = Progress {
            rng: me.rng.clone(),
            state: me.state.clone(),
            done: me.done,
            start: me.start,
            before_start: me.before_start.clone(),
            history: me.history.clone(),
        };
        let state =
            serde_json::to_string(&progress).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok((
            slf.get_type().into_any(),
            (
                me.scene.clone(),
                me.commands,
                observe_name(me.observe),
                me.use_reward,
            ),
            state,
        ))
    }

    fn __setstate__(&mut self, state: &str) -> PyResult<()> {
        let p: Progress = serde_json::from_str(state).map_err(|e| {
            PyValueError::new_err(format!("EpisodeWorld: not a pickled state: {e}"))
        })?;
        let starts = self.world().num_contexts();
        let replayable = p.before_start.is_none() || p.history.len() == p.done;
        if p.start >= starts.max(1) || p.done > self.commands || !replayable {
            return Err(PyValueError::new_err(format!(
                "EpisodeWorld: not a pickled state: start {} of {starts}, {} commands done of {}",
                p.start, p.done, self.commands
            )));
        }
        self.rng = p.rng;
        self.done = p.done;
        self.start = p.start;
        self.state = match (p.state, &p.before_start) {
            // rebuilt by drawing the start again from the same generator
            // and executing the same commands: the same bits, the physics
            // snapshot included
            (Some(_), Some(before)) => Some(self.replay(before.clone(), &p.history)?),
            (state, _) => state,
        };
        self.before_start = p.before_start;
        self.history = p.history;
        Ok(())
    }

    fn __repr__(&self) -> String {
        format!(
            "EpisodeWorld({}, commands={}, observe={:?})",
            self.scene.inner.spec().name,
            self.commands,
            observe_name(self.observe)
        )
    }
}
