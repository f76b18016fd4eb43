//! Scenes: the RON files that describe a world, its command schema, its
//! effects and its reward (`docs/scenes.md` documents every field).
//!
//! [`Scene::load`] parses and validates; every mistake is a [`SceneError`]
//! naming the file, the line and column, the field and what was expected.
//! A [`Scene`] is expanded (no shorthands, no templates), immutable and
//! known to be valid, so building its world cannot fail; a scene built or
//! edited in code is a [`SceneSpec`], which [`SceneSpec::validate`] turns
//! into a [`Scene`] and [`SceneSpec::to_ron`] writes as text.

/// The functions that give serde the defaults of fields
/// (`#[serde(default = "half")]`).
macro_rules! defaults {
    ($($name:ident: $t:ty = $v:expr;)*) => {$(
        fn $name() -> $t {
            $v
        }
    )*};
}

mod check;
pub mod enclosure;
mod error;
mod grid;
pub mod mjcf;
pub mod overlap;
pub mod path;
pub mod physics;
mod region;
pub mod shorthand;
pub mod symmetry;
pub mod template;
pub(crate) mod valid;

pub use error::{did_you_mean, SceneError, SceneErrorKind};
pub use grid::{GridSpec, StartCells};
pub use physics::PhysicsSpec;
pub use region::RegionSpec;
pub use shorthand::{ChainSpec, Each, LinkShape, Placement, WallSpec};
pub use symmetry::Symmetry;
pub use valid::Scene;

use crate::effect::EffectGrid;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// An editable scene: the fields of a scene file, public, with serde;
/// [`validate`](Self::validate) it into a [`Scene`], write it with
/// [`to_ron`](Self::to_ron).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "Scene")]
pub struct SceneSpec {
    /// The scene's name (used in errors, pictures and results).
    pub name: String,
    /// A sentence or two for people.
    #[serde(default)]
    pub description: String,
    /// What kind of world executes the commands.
    pub world: WorldSpec,
    /// The number of slots the command must have (default: not declared).
    /// A declared count is checked: a `Slots` list of another length is
    /// refused at load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slots: Option<usize>,
    /// The command schema: slots, their symbols and what each symbol does.
    pub command: CommandSpec,
    /// The reward (task 2). Without it, every reward is 0.
    #[serde(default)]
    pub reward: RewardSpec,
}

/// The kind of world a scene describes.
// A physics world is larger than a grid (its shorthand lists added the
// last 48 bytes); a scene is built once per run, and boxing it would change
// every `WorldSpec::Physics(p)` pattern of the API.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum WorldSpec {
    /// A grid of cells with walls between some neighbours; every symbol is a
    /// one-cell move ([`Action::Move`]). The effect is the terminal cell.
    Grid(GridSpec),
    /// Rigid bodies and revolute joints simulated by Rapier; symbols are
    /// torques, impulses, forces or joint targets. The effect is the cell
    /// of a tracked point (see [`physics`]).
    Physics(PhysicsSpec),
}

/// The command schema.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum CommandSpec {
    /// `slots` slots sharing one alphabet (the grid: 7 x {E, S, W, N}).
    Repeat {
        /// The number of slots `n`.
        slots: usize,
        /// The symbols every slot accepts.
        alphabet: Vec<SymbolSpec>,
    },
    /// One entry per slot, each with its own alphabet (the arm: slot k drives
    /// joint k).
    Slots(Vec<SlotSpec>),
    /// `slots` slots sharing one alphabet whose actions may name the joint
    /// or body `"*"`: in slot `k` it stands for `cycle[k mod m]` ("slot k
    /// drives joint k mod m"). Expanded at load into the equivalent
    /// [`Slots`](CommandSpec::Slots) (see [`template`]).
    Template {
        /// The number of slots `n`.
        slots: usize,
        /// The symbols every slot accepts; `"*"` as a joint or body name
        /// stands for the slot's entry of `cycle`.
        alphabet: Vec<SymbolSpec>,
        /// The joints or bodies the slots take in turn (default none: then
        /// no action may name `"*"`).
        #[serde(default)]
        cycle: Vec<String>,
    },
    /// Continuous commands (physics scenes): one entry per slot, each a
    /// range of values and what a value does, instead of an alphabet. Such
    /// a scene runs on live physics only ([`PhysicsWorld::execute_values`](crate::world::PhysicsWorld::execute_values)):
    /// outcome tables, the memo and the symbol learners do not apply.
    Continuous(Vec<ValueSlotSpec>),
}

/// One slot of a [`CommandSpec::Continuous`] schema: a value in `range`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ValueSlotSpec {
    /// An optional name, for pictures and errors.
    #[serde(default)]
    pub name: Option<String>,
    /// The values the slot accepts, `(min, max)` with `min < max`, in the
    /// unit of the action (N·m, rad, N·s, N).
    pub range: (f64, f64),
    /// What the slot's value does.
    pub action: ValueAction,
}

/// What the value `v` of a continuous slot does: the [`Action`] of
/// [`at`](ValueAction::at)`(v)`.
///
/// ```
/// use e3d::scene::{Action, ValueAction};
/// let kick = ValueAction::Heading { body: "puck".into(), impulse: 2.0 };
/// assert_eq!(kick.at(0.0), Action::Impulse { body: "puck".into(), impulse: (2.0, 0.0) });
/// let t = ValueAction::Torque { joint: "j1".into() };
/// assert_eq!(t.at(-0.5), Action::Torque { joint: "j1".into(), torque: -0.5 });
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum ValueAction {
    /// A torque of `v` N·m on a revolute joint, held during the slot's
    /// phase (as [`Action::Torque`]).
    Torque {
        /// The joint's name.
        joint: String,
    },
    /// A set point of `v` radians for a joint's position motor (as
    /// [`Action::Target`]; the joint needs a `motor`).
    Target {
        /// The joint's name.
        joint: String,
    },
    /// An impulse of `v * direction` N·s on a body, once at the start of
    /// the slot's phase (as [`Action::Impulse`]).
    Impulse {
        /// The body's name.
        body: String,
        /// The impulse of the value 1, `(x, y)` in N·s.
        direction: (f64, f64),
    },
    /// A force of `v * direction` N on a body, held during the slot's
    /// phase (as [`Action::Force`]).
    Force {
        /// The body's name.
        body: String,
        /// The force of the value 1, `(x, y)` in N.
        direction: (f64, f64),
    },
    /// An impulse of `impulse` N·s on a body in the direction `v`, in
    /// radians counter-clockwise from +x (a range of `(-3.14159, 3.14159)`
    /// covers every direction).
    Heading {
        /// The body's name.
        body: String,
        /// The impulse's magnitude in N·s.
        impulse: f64,
    },
}

impl ValueAction {
    /// The action of the value `v`.
    pub fn at(&self, v: f64) -> Action {
        match self {
            ValueAction::Torque { joint } => Action::Torque {
                joint: joint.clone(),
                torque: v,
            },
            ValueAction::Target { joint } => Action::Target {
                joint: joint.clone(),
                angle: v,
            },
            ValueAction::Impulse { body, direction } => Action::Impulse {
                body: body.clone(),
                impulse: (v * direction.0, v * direction.1),
            },
            ValueAction::Force { body, direction } => Action::Force {
                body: body.clone(),
                force: (v * direction.0, v * direction.1),
            },
            ValueAction::Heading { body, impulse } => Action::Impulse {
                body: body.clone(),
                impulse: (impulse * v.cos(), impulse * v.sin()),
            },
        }
    }
}

/// One slot of a [`CommandSpec::Slots`] schema.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlotSpec {
    /// An optional name, for pictures and errors.
    #[serde(default)]
    pub name: Option<String>,
    /// The symbols this slot accepts.
    pub alphabet: Vec<SymbolSpec>,
}

/// A symbol and what it does.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SymbolSpec {
    /// The character that stands for this symbol in written commands.
    pub symbol: char,
    /// What the symbol does when executed.
    pub action: Action,
}

/// What a symbol does.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Action {
    /// Nothing.
    Idle,
    /// Grid scenes: move by `(drow, dcol)` cells (one cell at most); a move
    /// into a wall or out of the grid leaves the agent where it is.
    Move {
        /// Rows to move (+1 is down, south).
        drow: i32,
        /// Columns to move (+1 is right, east).
        dcol: i32,
    },
    /// Physics scenes: a torque in N·m on a revolute joint (+torque on the
    /// child body, -torque on the parent, nothing on `ground`), held during
    /// the slot's phase.
    Torque {
        /// The joint's name.
        joint: String,
        /// The torque in N·m (counter-clockwise positive).
        torque: f64,
    },
    /// Physics scenes: an impulse in N·s on a body's centre of mass, once
    /// at the start of the slot's phase.
    Impulse {
        /// The body's name.
        body: String,
        /// The impulse `(x, y)` in N·s.
        impulse: (f64, f64),
    },
    /// Physics scenes: a force in N on a body's centre of mass, held
    /// during the slot's phase.
    Force {
        /// The body's name.
        body: String,
        /// The force `(x, y)` in N.
        force: (f64, f64),
    },
    /// Physics scenes: a new set point, from the start pose, for the
    /// position motor of a joint (which needs a `motor`): an angle in
    /// radians for a hinge, a position in metres along the axis for a
    /// slider; it holds until another `Target` on that joint.
    Target {
        /// The joint's name.
        joint: String,
        /// The target: radians for a hinge, metres for a slider (also
        /// written `position: p`).
        #[serde(alias = "position")]
        angle: f64,
    },
}

/// The reward: `value` when the terminal effect is one of `cells`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RewardSpec {
    /// The rewarded cells `(row, col)` of the effect grid.
    pub cells: Vec<(usize, usize)>,
    /// Named rectangles (metres): the cells whose centre lies inside are
    /// rewarded too.
    pub regions: Vec<RegionSpec>,
    /// The reward given in a rewarded cell (default 1).
    pub value: f64,
    /// Why these cells (for example the rule that chose them).
    pub note: String,
}

impl Default for RewardSpec {
    fn default() -> Self {
        RewardSpec {
            cells: Vec::new(),
            regions: Vec::new(),
            value: 1.0,
            note: String::new(),
        }
    }
}

macro_rules! builtin {
    ($($name:literal),*) => {
        &[$(($name, include_str!(concat!("../../scenes/", $name, ".ron")))),*]
    };
}

/// The scenes shipped in `scenes/`, built into the binary: `(name, RON text)`.
pub const BUILTIN: &[(&str, &str)] = builtin!(
    "two_rooms",
    "puck_rooms",
    "arm7",
    "pendulum3",
    "maze3",
    "puck_rooms14",
    "arm7x5",
    "three_rooms",
    "arm4_gravity",
    "arm7_continuous",
    "arm_push",
    "swimmer",
    "cart_pole",
    "four_rooms",
    "reacher",
    "swimmer_drag"
);

/// The scene [`Scene::resolve`] picks when none is named: `two_rooms`.
pub const DEFAULT_SCENE: &str = "two_rooms";

impl SceneSpec {
    /// Replaces the shorthands of a physics scene ([`shorthand`]) and a
    /// [`CommandSpec::Template`] by the plain bodies, joints and slots they
    /// stand for, without validating ([`validate`](Self::validate) expands too).
    ///
    /// ```
    /// use e3d::scene::{Scene, WorldSpec};
    /// let mut arm = Scene::builtin("arm7").unwrap().to_spec();
    /// let WorldSpec::Physics(p) = &mut arm.world else { unreachable!() };
    /// assert_eq!(p.bodies.len(), 7); // expanded at load
    /// p.chains.push(e3d::scene::ChainSpec { base: (0.0, 1.0), prefix: "b".into(),
    ///     joint_prefix: "k".into(), ..e3d::scene::ChainSpec::new(3, 0.2, 0.04) });
    /// arm.expand().unwrap();
    /// let WorldSpec::Physics(p) = &arm.world else { unreachable!() };
    /// // a chain's links come before the bodies written in `bodies`
    /// let names: Vec<&str> = p.bodies.iter().map(|b| b.name.as_str()).collect();
    /// assert_eq!(names[..4], ["b1", "b2", "b3", "link1"]);
    /// assert_eq!(p.bodies.len(), 10);
    /// assert_eq!(p.joints[3].name, "j1");
    /// ```
    pub fn expand(&mut self) -> Result<(), SceneError> {
        // a template mixing joints and bodies needs the joints' names
        let joints: Vec<String> = match &self.world {
            WorldSpec::Physics(p) if template::needs_joints(&self.command) => {
                let mut e = p.clone();
                shorthand::expand(&mut e).map_err(|v| self.invalid(v))?;
                e.joints.into_iter().map(|j| j.name).collect()
            }
            _ => Vec::new(),
        };
        let is_joint = |c: &str| joints.iter().any(|j| j == c);
        if let Some(slots) =
            template::expand(&self.command, &is_joint).map_err(|v| self.invalid(v))?
        {
            self.command = slots;
        }
        match &mut self.world {
            WorldSpec::Physics(p) if p.has_shorthands() => shorthand::expand(p).map(drop),
            _ => Ok(()),
        }
        .map_err(|v| self.invalid(v))
    }

    /// The error of a failure `v` of this spec, which has no text: its
    /// file `<scene NAME>`, no position.
    fn invalid(&self, v: Invalid) -> SceneError {
        SceneError::invalid(&format!("<scene {}>", self.name), v, None)
    }

    /// The alphabets, slot by slot (empty for the slots of a
    /// [`CommandSpec::Continuous`] schema, which take values).
    pub fn slots(&self) -> impl Iterator<Item = &[SymbolSpec]> + '_ {
        (0..self.num_slots()).map(move |i| match &self.command {
            CommandSpec::Repeat { alphabet, .. } | CommandSpec::Template { alphabet, .. } => {
                alphabet.as_slice()
            }
            CommandSpec::Slots(s) => s[i].alphabet.as_slice(),
            CommandSpec::Continuous(_) => &[],
        })
    }

    /// The number of slots of a command.
    pub fn num_slots(&self) -> usize {
        match &self.command {
            CommandSpec::Repeat { slots, .. } | CommandSpec::Template { slots, .. } => *slots,
            CommandSpec::Slots(s) => s.len(),
            CommandSpec::Continuous(s) => s.len(),
        }
    }

    /// Whether the scene's slots take values in ranges
    /// ([`CommandSpec::Continuous`]) rather than symbols.
    pub fn is_continuous(&self) -> bool {
        matches!(self.command, CommandSpec::Continuous(_))
    }

    /// `Ok` for a scene of symbols; for a continuous scene, the error that
    /// `what` (a tool: `"an outcome table"`, `"e3d sweep"`) cannot take it,
    /// naming the scene.
    pub fn require_symbols(&self, what: &str) -> Result<(), SceneError> {
        if !self.is_continuous() {
            return Ok(());
        }
        Err(self.invalid(Invalid::new(
            "command",
            format!(
                "symbols in every slot for {what}, but this scene's slots take values (`Continuous`): it runs on live physics with `e3d run` or `e3d scene exec` (docs/scenes.md, \"Continuous commands\")"
            ),
        )))
    }

    /// The grid effects are binned on; `None` for an effect that does not
    /// validate (a valid [`Scene`]'s is [`Scene::effect_grid`]).
    pub fn effect_grid(&self) -> Option<EffectGrid> {
        match &self.world {
            WorldSpec::Grid(g) => Some(g.effect_grid()),
            WorldSpec::Physics(p) => p.effect_grid(),
        }
    }

    /// The reward of each effect of `grid` (`value` on reward cells, 0
    /// elsewhere).
    pub(crate) fn reward_table_on(&self, g: &EffectGrid) -> Vec<f64> {
        let mut r = vec![0.0; g.num_cells()];
        let regions = self
            .reward
            .regions
            .iter()
            .flat_map(|region| region.cells(g));
        for (row, col) in self.reward.cells.iter().copied().chain(regions) {
            r[row * g.cols + col] = self.reward.value;
        }
        r
    }

    /// The simulation steps one command takes (`None` for worlds without
    /// time steps, like grids).
    pub fn steps_per_command(&self) -> Option<usize> {
        match &self.world {
            WorldSpec::Grid(_) => None,
            WorldSpec::Physics(p) => {
                Some(p.schedule.total_steps(p.dt, self.slots().count()) as usize)
            }
        }
    }

    /// Checks the spec and returns the [`Scene`] it describes, expanded and
    /// known to be valid: the checks [`Scene::load`] runs after reading the
    /// RON. The error is [`SceneErrorKind::Invalid`], with file `<scene NAME>`
    /// and no position.
    ///
    /// ```
    /// use e3d::scene::{Scene, SceneErrorKind, WorldSpec};
    ///
    /// let mut puck = Scene::builtin("puck_rooms").unwrap().to_spec();
    /// assert!(puck.validate().is_ok());
    /// if let WorldSpec::Physics(p) = &mut puck.world {
    ///     p.bodies.last_mut().unwrap().mass = Some(f64::NAN);
    /// }
    /// let err = puck.validate().unwrap_err();
    /// assert!(matches!(err.kind(), SceneErrorKind::Invalid { field, .. } if field == "mass"));
    /// assert_eq!(err.to_string(), "<scene puck_rooms>: field `mass`: expected body `puck`: a mass > 0 in kg, found NaN");
    /// ```
    pub fn validate(&self) -> Result<Scene, SceneError> {
        self.check().map_err(|v| self.invalid(v))?;
        let mut spec = self.clone();
        spec.expand()?;
        Scene::of_checked(spec).map_err(|v| self.invalid(v))
    }

    /// The scene as RON text in the scene files' dialect ([`ron_options`]),
    /// every field written: `Scene::parse(&s.to_ron(), f) == Ok(s)` for a valid
    /// scene (plain `ron::to_string` does not read back). A spec with `chains`
    /// or `walls` is written with them, and reads back expanded.
    ///
    /// ```
    /// use e3d::Scene;
    /// let arm = Scene::builtin("arm7").unwrap();
    /// let text = arm.spec().to_ron();
    /// assert!(text.starts_with("Scene(\n    name: \"arm7\","));
    /// assert_eq!(Scene::parse(&text, "arm7.ron").unwrap(), arm);
    /// ```
    pub fn to_ron(&self) -> String {
        let pretty = ron::ser::PrettyConfig::new();
        let body = ron_options()
            .to_string_pretty(self, pretty)
            .expect("a scene is plain data: it always serialises");
        // ron writes structs without their names: name the outer one, as
        // scene files do
        format!("Scene{body}\n")
    }
}

/// The text of a scene or sweep file as RON reads it: a UTF-8 byte order
/// mark (which some editors write) is dropped; CR-only line endings (old
/// Mac files), which RON reads as one line, are refused with a message.
pub(crate) fn prepare_text<'a>(
    text: &'a str,
    file: &str,
    kind: &'static str,
) -> Result<&'a str, SceneError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.contains('\r') && !text.contains('\n') {
        return Err(SceneError::new(file, kind, SceneErrorKind::CrLineEndings));
    }
    Ok(text)
}

/// Whether `c` can stand for a symbol in a written command: one visible
/// character, not `,` or `"` (commands are unquoted CSV fields), not
/// whitespace, a control, format (zero-width) or combining character.
pub fn printable_symbol(c: char) -> bool {
    use unicode_width::UnicodeWidthChar;
    !(c.is_whitespace() || c.is_control() || c == ',' || c == '"')
        && c.width().is_some_and(|w| w > 0)
}

/// The most start contexts a scene may declare (1024): each is a start
/// the tools run, table, draw and report one by one; a scene file of a few
/// kB could otherwise declare 10^5 of them, whose tables (one per context)
/// took gigabytes.
pub const MAX_CONTEXTS: usize = 1024;

/// Refuses more than [`MAX_CONTEXTS`] start contexts, before any of them
/// is checked.
pub(crate) fn check_context_count(n: usize) -> Result<(), Invalid> {
    if n > MAX_CONTEXTS {
        return Err(Invalid::new(
            "contexts",
            format!("at most {MAX_CONTEXTS} start contexts (e3d::scene::MAX_CONTEXTS), found {n}"),
        ));
    }
    Ok(())
}

/// The largest reward value a scene may give, in magnitude (1e12): a
/// cumulative reward over the most trials a run or sweep allows (10^8)
/// stays far from overflowing, so no metric is infinite.
pub const MAX_REWARD: f64 = 1e12;

/// The largest scene or sweep file read, in bytes (16 MiB): the shipped
/// scenes hold a few kB; anything larger is a wrong path.
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// Reads a RON file of the given kind (`scene`, `sweep`) as text: a
/// directory, an unreadable file or bytes that are not UTF-8 are errors
/// that name the file (and, for bad bytes, where they start).
pub(crate) fn read_text(path: &Path, kind: &'static str) -> Result<String, SceneError> {
    use std::io::Read;
    let file = path.display().to_string();
    let error = |k: SceneErrorKind| SceneError::new(&file, kind, k);
    if path.is_dir() {
        return Err(error(SceneErrorKind::Directory));
    }
    let cannot = |e: std::io::Error| error(SceneErrorKind::Io(e));
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if !meta.is_file() {
        // a FIFO would block for ever, a device like /dev/zero never end
        return Err(error(SceneErrorKind::NotRegularFile));
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(error(SceneErrorKind::TooLarge {
            bytes: Some(meta.len()),
        }));
    }
    // read at most one byte more than allowed (the file may grow meanwhile)
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    let f = std::fs::File::open(path).map_err(cannot)?;
    (f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes)).map_err(cannot)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(error(SceneErrorKind::TooLarge { bytes: None }));
    }
    String::from_utf8(bytes).map_err(|e| {
        let upto = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let (line, col) = error::position_at(&String::from_utf8_lossy(upto), upto.len());
        error(SceneErrorKind::NotUtf8 {
            line,
            col,
            error: e.utf8_error(),
        })
    })
}

/// The RON dialect of scene files: newtype variants may be written without
/// their inner parentheses (`Grid(rows: 3, ...)`), and optional fields
/// without `Some(...)`.
pub fn ron_options() -> ron::Options {
    use ron::extensions::Extensions;
    ron::Options::default()
        .with_default_extension(Extensions::UNWRAP_VARIANT_NEWTYPES | Extensions::IMPLICIT_SOME)
}

/// A validation failure, before it is placed in the file.
#[derive(Debug)]
pub(crate) struct Invalid {
    /// The field at fault.
    pub field: String,
    /// A text near the fault (for example `name: "puck"`), searched first.
    pub anchor: Option<String>,
    /// Which occurrence of the field after the anchor (0 = first).
    pub nth: usize,
    /// What was expected (and what was found).
    pub expected: String,
    /// An entry of a list of shorthands (`("chains", 2)`): the field is
    /// looked for inside that entry (at its start if not written there).
    pub within: Option<(&'static str, usize)>,
}

impl Invalid {
    /// A failure at the first `field` of the file.
    pub(crate) fn new(field: &str, expected: impl Into<String>) -> Invalid {
        Invalid {
            field: field.to_string(),
            anchor: None,
            nth: 0,
            expected: expected.into(),
            within: None,
        }
    }

    /// A failure at `field`, searched after `anchor` if given.
    pub(crate) fn at(field: &str, anchor: Option<&str>, expected: &str) -> Invalid {
        Invalid {
            anchor: anchor.map(str::to_string),
            ..Invalid::new(field, expected)
        }
    }

    /// An error on a generated body or joint placed at the shorthand that
    /// generated it (by the name it is anchored on).
    fn attributed(mut self, origins: &shorthand::Origins) -> Invalid {
        if self.within.is_none() {
            let name = self.anchor.as_deref().map(|a| a.trim_matches('"'));
            if let Some(&(list, k)) = name.and_then(|n| origins.get(n)) {
                self.within = Some((list, k));
                self.expected = format!("{} (generated by {list}[{k}])", self.expected);
            }
        }
        self
    }

    /// The failure in entry `k` of the list field `list`.
    fn within(mut self, list: &'static str, k: usize) -> Invalid {
        self.within = Some((list, k));
        self
    }

    fn nth(mut self, n: usize) -> Invalid {
        self.nth = n;
        self
    }
}
