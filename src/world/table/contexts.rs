//! The outcome tables of a scene's named start contexts: the table keyed
//! by `(context, command)`.

use super::file::file_safe;
use super::*;
use crate::rng::SessionRng;
use crate::world::Control;
use crate::world::{Episodic, WorldState};
use rand::SeedableRng;

/// One start context of a scene, as the scene tools show it: its name and
/// whether its start is drawn from a range (a *drawn* context, which runs
/// live and has no table).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StartContext {
    /// The context's name.
    pub name: String,
    /// Whether its start is drawn from a range at each episode.
    pub drawn: bool,
}

/// The start contexts a scene declares, in order (empty for a scene
/// without `contexts`).
///
/// ```
/// use e3d::world::start_contexts;
/// use e3d::Scene;
/// let puck = Scene::load("scenes/puck_contexts.ron").unwrap();
/// let c = start_contexts(&puck);
/// assert_eq!(c.len(), 2);
/// assert!(c.iter().all(|c| !c.drawn));
/// assert!(start_contexts(&Scene::builtin("two_rooms").unwrap()).is_empty());
/// ```
pub fn start_contexts(scene: &Scene) -> Vec<StartContext> {
    match &scene.spec().world {
        WorldSpec::Grid(g) => g
            .contexts
            .iter()
            .map(|c| StartContext {
                name: c.name.clone(),
                drawn: c.to.is_some_and(|to| to != c.cell),
            })
            .collect(),
        WorldSpec::Physics(p) => p
            .contexts
            .iter()
            .map(|c| StartContext {
                name: c.name.clone(),
                drawn: c.is_sampled(),
            })
            .collect(),
    }
}

/// The name of start context `k` of `scene` ("" past its contexts), in
/// constant time (collecting every context for one name made the tools
/// quadratic in the contexts).
fn context_name(scene: &Scene, k: usize) -> &str {
    match &scene.spec().world {
        WorldSpec::Grid(g) => g.contexts.get(k).map_or("", |c| c.name.as_str()),
        WorldSpec::Physics(p) => p.contexts.get(k).map_or("", |c| c.name.as_str()),
    }
}

/// The start of context `k` of `world` as the scene tools use it: a named
/// context's start, or a drawn context's draw with seed 0 (the start
/// `e3d scene exec` and `e3d scene render` show).
pub fn seed0_start(world: &dyn Episodic, k: usize) -> Result<WorldState, WorldError> {
    world.draw_start(k, &mut SessionRng::seed_from_u64(0))
}

/// Every command of a scene executed once from the start of each of its
/// named start contexts: the outcome table keyed by `(context, command)`.
/// A scene whose contexts are all named has one; a drawn context (a range
/// of starts) cannot be tabled.
///
/// ```
/// use e3d::world::ContextTables;
/// use e3d::{Scene, World};
/// let scene = Scene::load("scenes/two_rooms_contexts.ron").unwrap();
/// let tables = ContextTables::build(&scene).unwrap();
/// assert_eq!(tables.names(), ["room_a", "room_b"]);
/// let c = scene.command_space().parse("EEEEESS").unwrap();
/// let mut world = scene.build();
/// let mut rng = <e3d::rng::SessionRng as rand::SeedableRng>::seed_from_u64(0);
/// let from = world.draw_start(1, &mut rng).unwrap();
/// let o = world.execute_outcome_from(&from, &c).unwrap();
/// assert_eq!(tables.table(1).lookup(&c).unwrap(), &o);
/// assert_ne!(tables.table(0).lookup(&c).unwrap(), &o);
/// ```
#[derive(Debug, Clone)]
pub struct ContextTables {
    names: Vec<String>,
    tables: Vec<OutcomeTable>,
}

/// A scene whose start contexts are all named: what a [`ContextTables`]
/// is built for (see [`TabledContexts::of`]).
#[derive(Debug, Clone, Copy)]
pub struct TabledContexts<'s> {
    scene: &'s Scene,
    count: usize,
}

impl<'s> TabledContexts<'s> {
    /// `scene`, if it has start contexts, all named, and a command space
    /// small enough for tables; else why not, naming the first drawn
    /// context.
    pub fn of(scene: &'s Scene) -> Result<TabledContexts<'s>, WorldError> {
        let contexts = start_contexts(scene);
        let name = &scene.spec().name;
        if contexts.is_empty() {
            return Err(WorldError::Other(format!(
                "scene `{name}` has no start contexts: its table is the plain outcome table"
            )));
        }
        if let Some(c) = contexts.iter().find(|c| c.drawn) {
            return Err(WorldError::Other(format!(
                "scene `{name}`: context `{}` is drawn from a range (a `to` field): its starts are not a fixed state, so it cannot be tabled (its commands run live); a table needs every context named",
                c.name
            )));
        }
        if scene.spec().is_continuous() {
            return Err(WorldError::Other(format!(
                "scene `{name}`: its slots take values (`Continuous`): no table"
            )));
        }
        let n = OutcomeTable::check_size(&scene.command_space())?;
        // the outcomes of every context's table together are bounded as
        // one table's are
        let total = n.saturating_mul(contexts.len() as u64);
        if total > MAX_TABLE_COMMANDS {
            return Err(WorldError::Other(format!(
                "scene `{}`: {} contexts x {n} commands = {total} outcomes: too many for the tables of its contexts (at most {MAX_TABLE_COMMANDS} in all); run it live (`e3d run`, `e3d scene exec` without a table)",
                crate::text::echo(name),
                contexts.len()
            )));
        }
        Ok(TabledContexts {
            scene,
            count: contexts.len(),
        })
    }

    /// The number of contexts.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Never empty (a scene with contexts has one at least).
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The commands simulated for the tables: every command from every
    /// context.
    pub fn simulated_commands(&self) -> u64 {
        let n = self.scene.command_space().num_commands().unwrap_or(0);
        n * self.count as u64
    }
}

impl ContextTables {
    /// The tables of `scene`'s contexts, computed in parallel (rayon).
    pub fn build(scene: &Scene) -> Result<ContextTables, WorldError> {
        Self::build_with(TabledContexts::of(scene)?, &Control::default())
    }

    /// The tables of `contexts`, in parallel (rayon: one world per
    /// worker), calling `progress` with the number of commands of each
    /// chunk done. Every command runs from the context's start exactly as
    /// [`Episodic::execute_outcome_from`] runs it: the same outcomes, bit
    /// for bit, whatever the threads.
    pub fn build_with(
        contexts: TabledContexts<'_>,
        control: &Control<'_>,
    ) -> Result<ContextTables, WorldError> {
        let scene = contexts.scene;
        let space = scene.command_space();
        let n = OutcomeTable::check_size(&space)?;
        let probe = scene.build();
        let starts: Vec<WorldState> = (0..contexts.count)
            .map(|k| seed0_start(&probe, k))
            .collect::<Result<_, _>>()?;
        drop(probe);
        let tables = starts
            .iter()
            .map(|from| {
                let run = |w: &mut Box<dyn Episodic + Send>, cmds: &[Command], out: &mut Vec<_>| {
                    out.extend(cmds.iter().map(|c| w.execute_outcome_from(from, c)))
                };
                let outcomes = run_chunks(&space, n, |i| i, || scene.build(), run, control)?;
                Ok(OutcomeTable::new(
                    space.clone(),
                    scene.num_effects(),
                    outcomes,
                ))
            })
            .collect::<Result<Vec<_>, WorldError>>()?;
        Ok(ContextTables {
            names: start_contexts(scene).into_iter().map(|c| c.name).collect(),
            tables,
        })
    }

    /// The tables of `scene`'s contexts: read from `dir` where a whole
    /// table of the context is there ([`cache_path`](Self::cache_path)),
    /// the others computed and written there (each whole or not at all).
    /// Also whether every table was read.
    pub fn cached(
        contexts: TabledContexts<'_>,
        dir: &Path,
        control: &Control<'_>,
    ) -> Result<(ContextTables, bool), WorldError> {
        let scene = contexts.scene;
        crate::io::remove_stale_temps(dir);
        let read: Option<Vec<OutcomeTable>> = Self::read_cached(scene, dir).into_iter().collect();
        if let Some(tables) = read {
            let names = start_contexts(scene).into_iter().map(|c| c.name).collect();
            return Ok((ContextTables { names, tables }, true));
        }
        let built = Self::build_with(contexts, control)?;
        for (k, t) in built.tables.iter().enumerate() {
            // a cache that cannot be written is not an error: it costs time only
            let _ = t.write_file_keyed(&Self::cache_path(scene, dir, k), Self::key(scene, k));
        }
        Ok((built, false))
    }

    /// The whole tables of `scene`'s contexts that the folder `dir` holds
    /// (as [`cached`](Self::cached) writes them), in context order: `None`
    /// for a context whose table is not there, not whole or not this
    /// scene's. Nothing is computed or written.
    pub fn read_cached(scene: &Scene, dir: &Path) -> Vec<Option<OutcomeTable>> {
        (0..start_contexts(scene).len())
            .map(|k| {
                let path = Self::cache_path(scene, dir, k);
                match OutcomeTable::read_file_keyed(&path, scene, Self::key(scene, k)) {
                    Ok(CachedOutcomes::Full(t)) => Some(t),
                    _ => None,
                }
            })
            .collect()
    }

    /// The key of context `k`'s table: the scene's
    /// ([`OutcomeTable::key`]) with the context's index and name.
    pub fn key(scene: &Scene, k: usize) -> u64 {
        let name = context_name(scene, k);
        let text = format!("{:016x} context {k} {name}", OutcomeTable::key(scene));
        crate::hash::fnv1a64(text.as_bytes())
    }

    /// The file of context `k`'s table in the folder `dir`:
    /// `NAME-KEY.e3dtable`, NAME the scene's then the context's, KEY
    /// [`key`](Self::key) (the same format as a plain table's file).
    pub fn cache_path(scene: &Scene, dir: &Path, k: usize) -> PathBuf {
        let context = context_name(scene, k);
        dir.join(format!(
            "{}.{}-{:016x}.e3dtable",
            file_safe(&scene.spec().name),
            file_safe(context),
            Self::key(scene, k)
        ))
    }

    /// The number of contexts.
    pub fn len(&self) -> usize {
        self.tables.len()
    }

    /// Never empty.
    pub fn is_empty(&self) -> bool {
        self.tables.is_empty()
    }

    /// The contexts' names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The table of context `k` (`< len()`).
    pub fn table(&self, k: usize) -> &OutcomeTable {
        &self.tables[k]
    }

    /// The tables, in context order.
    pub fn tables(&self) -> &[OutcomeTable] {
        &self.tables
    }
}
