//! A valid scene: what [`SceneSpec::validate`] and the loaders return,
//! expanded, immutable and known to be valid, with what its worlds are
//! built from (its command space, a physics scene's names resolved to
//! indices, a symmetry's symbol maps) computed once, at validation.

use super::physics::{MotorSpec, PhysicsSpec, GROUND};
use super::symmetry::Symmetry;
use super::{
    prepare_text, read_text, ron_options, Action, CommandSpec, Invalid, SceneError, SceneErrorKind,
    SceneSpec, ValueAction, WorldSpec, BUILTIN,
};
use crate::command::{CommandSpace, ValueSpace};
use crate::effect::{Binning, EffectGrid, Feature};
use std::path::Path;

/// A scene known to be valid: made only by the loaders and
/// [`SceneSpec::validate`], expanded and immutable. Its fields are read
/// through [`spec`](Self::spec); to edit it, take its spec
/// ([`to_spec`](Self::to_spec)) and validate it again.
///
/// ```
/// use e3d::scene::{Scene, WorldSpec};
/// let arm = Scene::builtin("arm7").unwrap();
/// assert_eq!(arm.spec().name, "arm7");
/// let mut spec = arm.to_spec();
/// spec.name = "arm7b".into();
/// let edited = spec.validate().unwrap();
/// assert_eq!(edited.spec().name, "arm7b");
/// assert_eq!(edited.command_space(), arm.command_space());
/// ```
#[derive(Debug, Clone)]
pub struct Scene {
    spec: SceneSpec,
    space: CommandSpace,
    values: Option<ValueSpace>,
    mirror: Option<(Symmetry, Vec<Vec<u8>>)>,
    links: Links,
    binning: Binning,
}

/// A physics scene's names resolved to indices into its bodies and
/// joints, once, at validation (the worlds are built from these); empty
/// for a grid scene.
#[derive(Debug, Clone, Default)]
pub(crate) struct Links {
    /// Per joint: its parent body (`None`: ground) and its child body.
    pub joints: Vec<(Option<usize>, usize)>,
    /// The tracked body (the body whose point the pictures draw).
    pub tracked: usize,
    /// The tracked point, in the tracked body's frame.
    pub tracked_point: (f64, f64),
    /// What each feature of the effect reads, in the effect's order.
    pub probes: Vec<ResolvedProbe>,
    /// What each symbol does, slot by slot, in alphabet order.
    pub symbols: Vec<Resolved>,
    /// What each continuous slot's value does.
    pub values: Vec<ResolvedValue>,
    /// The joints, known to form a forest.
    pub forest: Forest,
    /// Per start context, in the spec's order: the indices of its bodies
    /// and of its joints, in the context's order.
    pub contexts: Vec<(Vec<usize>, Vec<usize>)>,
}

/// A physics scene's joints, known to form a forest: every body is the
/// child of one joint at most, and no joint closes a loop (the only
/// joints Rapier's multibodies refuse). Made only by [`Forest::of`].
#[derive(Debug, Clone, Default)]
pub(crate) struct Forest {
    /// Per joint: whether its tree hangs from ground.
    hung: Vec<bool>,
}

impl Forest {
    /// The forest of `joints` (per joint: its parent body, `None` for
    /// ground, and its child body) on `bodies` bodies, which
    /// [`SceneSpec::check`] found to form one.
    fn of(joints: &[(Option<usize>, usize)], bodies: usize) -> Forest {
        let mut parent_of = vec![None; bodies];
        for (k, &(_, child)) in joints.iter().enumerate() {
            parent_of[child] = Some(k);
        }
        // walk up from each parent to ground or a root body
        let hung = joints
            .iter()
            .map(|&(mut up, _)| {
                for _ in 0..=bodies {
                    match up.map(|b| parent_of[b]) {
                        None => return true,
                        Some(None) => return false,
                        Some(Some(k)) => up = joints[k].0,
                    }
                }
                false
            })
            .collect();
        Forest { hung }
    }

    /// Whether joint `joint`'s tree hangs from ground: such a tree is one
    /// Rapier multibody (see [`PhysicsSpec::hangs_from_ground`]).
    pub fn hangs_from_ground(&self, joint: usize) -> bool {
        self.hung[joint]
    }
}

/// A feature of the effect with its body or joint as an index.
#[derive(Debug, Clone)]
pub(crate) enum ResolvedProbe {
    /// A point of `body`, in the world or in `frame`'s body frame.
    Point {
        /// The body.
        body: usize,
        /// The point, in the body's frame.
        point: (f64, f64),
        /// The body whose frame the point is read in (`None`: the world).
        frame: Option<usize>,
    },
    /// A joint's coordinate.
    Joint(usize),
    /// A body's angle.
    Angle(usize),
    /// The centre of mass of these bodies.
    Centre(Vec<usize>),
}

/// An [`Action`] with its joint or body as an index.
#[derive(Debug, Clone)]
pub(crate) enum Resolved {
    /// Nothing (also a grid move, which a physics world ignores).
    Idle,
    /// A torque on joint `joint`.
    Torque { joint: usize, torque: f64 },
    /// An impulse on body `body`.
    Impulse { body: usize, impulse: (f64, f64) },
    /// A force on body `body`.
    Force { body: usize, force: (f64, f64) },
    /// A set point for joint `joint`'s motor.
    Target {
        joint: usize,
        angle: f64,
        motor: MotorSpec,
    },
}

/// A [`ValueAction`] with its joint or body as an index.
#[derive(Debug, Clone)]
pub(crate) enum ResolvedValue {
    /// An impulse of a fixed magnitude in the direction of the value.
    Heading { body: usize, impulse: f64 },
    /// The action of the value 1, scaled by the value.
    Scaled(Resolved),
}

impl PartialEq for Scene {
    /// Two scenes are equal when their specs are (everything else is
    /// computed from the spec).
    fn eq(&self, other: &Scene) -> bool {
        self.spec == other.spec
    }
}

impl serde::Serialize for Scene {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.spec.serialize(s)
    }
}

impl Scene {
    /// Loads and validates a scene file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = read_text(path, "scene")?;
        Scene::parse(&text, &path.display().to_string())
    }

    /// Parses and validates scene text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
        let text = prepare_text(text, file, "scene")?;
        if text.trim().is_empty() {
            return Err(SceneError::new(file, "scene", SceneErrorKind::Empty));
        }
        let mut spec: SceneSpec = ron_options()
            .from_str(text)
            .map_err(|e| SceneError::from_ron(file, text, e))?;
        // the checks of `validate` (on the expanded shorthands), the
        // failure placed in the text
        spec.check()
            .map_err(|v| SceneError::from_validation(file, text, v))?;
        // a scene holds plain bodies, joints and slots only
        spec.expand()?;
        Scene::of_checked(spec).map_err(|v| SceneError::from_validation(file, text, v))
    }

    /// A scene shipped with e3d, by name (see [`BUILTIN`]).
    pub fn builtin(name: &str) -> Option<Scene> {
        BUILTIN.iter().find(|(n, _)| *n == name).map(|(n, text)| {
            Scene::parse(text, &format!("<builtin {n}>")).expect("shipped scenes are valid")
        })
    }

    /// A scene by path, or by the name of a built-in scene when no such
    /// file exists.
    pub fn resolve(path_or_name: &str) -> Result<Scene, SceneError> {
        let p = Path::new(path_or_name);
        if p.exists() {
            return Scene::load(p);
        }
        Scene::builtin(path_or_name)
            .ok_or_else(|| SceneError::new(path_or_name, "scene", SceneErrorKind::NoSuchScene))
    }

    /// The scene whose command is `moves` moves of its `Repeat` alphabet
    /// (every other field the same), validated again; `None` when its
    /// command is not `Repeat` (its slots differ: nothing to repeat).
    /// `with_moves(1)` is the scene of per-move Q-learning
    /// (`qlearning_moves`): an episode of `K n` one-move commands spends
    /// the moves of `K` commands of `n`.
    ///
    /// ```
    /// use e3d::Scene;
    /// let scene = Scene::builtin("four_rooms").unwrap();
    /// let single = scene.with_moves(1).unwrap().unwrap();
    /// assert_eq!((scene.spec().num_slots(), single.spec().num_slots()), (5, 1));
    /// assert!(Scene::builtin("arm7").unwrap().with_moves(1).is_none());
    /// ```
    pub fn with_moves(&self, moves: usize) -> Option<Result<Scene, SceneError>> {
        let mut spec = self.to_spec();
        match &mut spec.command {
            super::CommandSpec::Repeat { slots, .. } => *slots = moves,
            _ => return None,
        }
        spec.slots = None;
        Some(spec.validate())
    }

    /// The scene's spec, to read (`scene.spec().name`).
    pub fn spec(&self) -> &SceneSpec {
        &self.spec
    }

    /// A copy of the scene's spec, to edit and validate again.
    pub fn to_spec(&self) -> SceneSpec {
        self.spec.clone()
    }

    /// The scene's spec, to edit and validate again.
    pub fn into_spec(self) -> SceneSpec {
        self.spec
    }

    /// The command space of this scene. A continuous scene's is a
    /// placeholder of one symbol, `~`, per slot (its commands are values:
    /// see [`value_space`](Self::value_space)).
    pub fn command_space(&self) -> CommandSpace {
        self.space.clone()
    }

    /// The command space of a continuous scene (`None` for a scene of
    /// symbols, whose space is [`command_space`](Self::command_space)).
    pub fn value_space(&self) -> Option<ValueSpace> {
        self.values.clone()
    }

    /// The value space of a continuous scene, borrowed.
    pub(crate) fn values(&self) -> Option<&ValueSpace> {
        self.values.as_ref()
    }

    /// How the scene's terminal states are binned into effects (a grid
    /// scene's: its cells).
    pub fn binning(&self) -> &Binning {
        &self.binning
    }

    /// The grid effects are binned on: the tracked point's grid, or the
    /// layout of the features' product (see [`Binning`]).
    pub fn effect_grid(&self) -> EffectGrid {
        self.binning.layout().clone()
    }

    /// The number of effects.
    pub fn num_effects(&self) -> usize {
        self.binning.num_effects()
    }

    /// The reward of each effect (`value` on reward cells, 0 elsewhere).
    pub fn reward_table(&self) -> Vec<f64> {
        self.spec.reward_table_on(&self.effect_grid())
    }

    /// A physics scene's names resolved to indices (empty for a grid).
    pub(crate) fn links(&self) -> &Links {
        &self.links
    }

    /// A physics scene's declared symmetry with its symbol maps (see
    /// [`Symmetry`]).
    pub(crate) fn mirror(&self) -> Option<&(Symmetry, Vec<Vec<u8>>)> {
        self.mirror.as_ref()
    }

    /// The scene of a spec that passed [`SceneSpec::check`] and was
    /// expanded: its command space, links and symbol maps. Their errors
    /// are those the checks already refused (kept as errors, not panics).
    pub(super) fn of_checked(spec: SceneSpec) -> Result<Scene, Invalid> {
        let invalid = |e: &dyn std::fmt::Display| Invalid::new("command", e.to_string());
        let values = match &spec.command {
            CommandSpec::Continuous(s) => Some(
                ValueSpace::new(s.iter().map(|v| v.range).collect()).map_err(|e| invalid(&e))?,
            ),
            _ => None,
        };
        let space = match &values {
            // a placeholder (one symbol per slot) that no command of
            // symbols passes (`check_command`)
            Some(v) => CommandSpace::repeat(v.num_slots(), &['~']),
            None => CommandSpace::new(
                spec.slots()
                    .map(|a| a.iter().map(|s| s.symbol).collect())
                    .collect(),
            ),
        }
        .map_err(|e| invalid(&e))?;
        let (links, mirror) = match &spec.world {
            WorldSpec::Physics(p) => (
                Links::of(&spec, p)?,
                p.symmetry
                    .map(|sym| sym.symbol_maps(&spec).map(|m| (sym, m)))
                    .transpose()?,
            ),
            WorldSpec::Grid(_) => (Links::default(), None),
        };
        let binning = match &spec.world {
            WorldSpec::Grid(g) => Binning::point(g.effect_grid()),
            WorldSpec::Physics(p) => {
                Binning::new(p.effect.features().iter().map(Feature::axis).collect())
            }
        }
        .map_err(|e| Invalid::new("effect", e.to_string()))?;
        Ok(Scene {
            spec,
            space,
            values,
            mirror,
            links,
            binning,
        })
    }
}

impl Links {
    /// The links of `scene`, whose world is `p`; an error names a body or
    /// joint not found (which [`SceneSpec::check`] refused already).
    fn of(scene: &SceneSpec, p: &PhysicsSpec) -> Result<Links, Invalid> {
        let names = Names(p);
        let joints: Vec<(Option<usize>, usize)> = p
            .joints
            .iter()
            .map(|j| {
                let parent = (j.parent != GROUND).then(|| names.body(&j.parent));
                Ok((parent.transpose()?, names.body(&j.child)?))
            })
            .collect::<Result<_, Invalid>>()?;
        let forest = Forest::of(&joints, p.bodies.len());
        let contexts = p
            .contexts
            .iter()
            .map(|c| {
                let bodies = c.bodies.iter().map(|b| names.body(&b.body));
                let joints = c.joints.iter().map(|j| names.joint(&j.joint));
                Ok((
                    bodies.collect::<Result<_, _>>()?,
                    joints.collect::<Result<_, _>>()?,
                ))
            })
            .collect::<Result<_, Invalid>>()?;
        let symbols = scene
            .slots()
            .flatten()
            .map(|s| names.action(&s.action))
            .collect::<Result<_, Invalid>>()?;
        let values = match &scene.command {
            CommandSpec::Continuous(slots) => slots
                .iter()
                .map(|slot| {
                    Ok(match &slot.action {
                        ValueAction::Heading { body: b, impulse } => ResolvedValue::Heading {
                            body: names.body(b)?,
                            impulse: *impulse,
                        },
                        a => ResolvedValue::Scaled(names.action(&a.at(1.0))?),
                    })
                })
                .collect::<Result<_, Invalid>>()?,
            _ => Vec::new(),
        };
        let (drawn, tracked_point) = p
            .effect
            .drawn_point(|j| p.child_of(j))
            .ok_or_else(|| Invalid::new("effect", "an effect with at least one feature"))?;
        let probes = names.probes()?;
        Ok(Links {
            joints,
            tracked: names.body(drawn)?,
            tracked_point,
            probes,
            symbols,
            values,
            forest,
            contexts,
        })
    }
}

/// A physics world's names of bodies and joints, to resolve to indices.
struct Names<'a>(&'a PhysicsSpec);

impl Names<'_> {
    /// The index of body `name`.
    fn body(&self, name: &str) -> Result<usize, Invalid> {
        let i = self.0.body_index(name);
        i.ok_or_else(|| Invalid::new("body", format!("a known body, found `{name}`")))
    }

    /// The index of joint `name`.
    fn joint(&self, name: &str) -> Result<usize, Invalid> {
        let i = self.0.joints.iter().position(|j| j.name == name);
        i.ok_or_else(|| Invalid::new("joint", format!("a known joint, found `{name}`")))
    }

    /// `action` with its joint or body as an index (a target's joint with
    /// its motor).
    fn action(&self, action: &Action) -> Result<Resolved, Invalid> {
        Ok(match action {
            Action::Idle | Action::Move { .. } => Resolved::Idle,
            Action::Torque { joint: j, torque } => Resolved::Torque {
                joint: self.joint(j)?,
                torque: *torque,
            },
            Action::Impulse { body: b, impulse } => Resolved::Impulse {
                body: self.body(b)?,
                impulse: *impulse,
            },
            Action::Force { body: b, force } => Resolved::Force {
                body: self.body(b)?,
                force: *force,
            },
            Action::Target { joint: j, angle } => {
                let k = self.joint(j)?;
                let motor = self.0.joints[k]
                    .motor
                    .ok_or_else(|| Invalid::new("joint", format!("joint `{j}` with a motor")))?;
                Resolved::Target {
                    joint: k,
                    angle: *angle,
                    motor,
                }
            }
        })
    }

    /// What each feature of the effect reads, in the effect's order.
    fn probes(&self) -> Result<Vec<ResolvedProbe>, Invalid> {
        self.0
            .effect
            .features()
            .iter()
            .map(|f| {
                Ok(match f {
                    Feature::Point {
                        body: b,
                        point,
                        frame,
                        ..
                    } => ResolvedProbe::Point {
                        body: self.body(b)?,
                        point: *point,
                        frame: frame.as_deref().map(|f| self.body(f)).transpose()?,
                    },
                    Feature::Joint { joint: j, .. } => ResolvedProbe::Joint(self.joint(j)?),
                    Feature::Angle { body: b, .. } => ResolvedProbe::Angle(self.body(b)?),
                    Feature::Centre { bodies, .. } => ResolvedProbe::Centre(
                        bodies
                            .iter()
                            .map(|b| self.body(b))
                            .collect::<Result<_, _>>()?,
                    ),
                })
            })
            .collect()
    }
}
