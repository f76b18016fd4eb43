//! Seeded noise in a physics world: each execution of a command scales
//! its actions by drawn factors, offsets the start of some free bodies by
//! drawn amounts and scales bodies' numbers. The draws come from
//! generators keyed by the session's seed and the trial ([`DrawKey`]),
//! never from thread order.

use crate::rng::SessionRng;
use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};

/// The `noise` section of a physics world (default none: every execution
/// of a command gives the same bits). Each execution draws the start
/// offsets, then the bodies' factors, then one factor per slot.
///
/// ```ron
/// noise: (
///     actions: Gaussian(sd: 0.05),
///     starts: [(body: "puck", position: Uniform(half_width: 0.02), angle: Gaussian(sd: 0.05))],
///     body_numbers: [
///         (body: "puck", mass: Gaussian(sd: 0.1), linear_damping: Uniform(half_width: 0.2)),
///         (body: "puck", per: Session, friction: Uniform(half_width: 0.3)),
///     ],
/// ),
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseSpec {
    /// Each slot's action (a torque, force, impulse or joint target) is
    /// multiplied by `1 + x`, `x` drawn from this spread anew for every
    /// slot of every execution (default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub actions: Option<Spread>,
    /// Free bodies and joints whose start is offset at every execution
    /// (default none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub starts: Vec<StartNoise>,
    /// Free bodies whose physical numbers are multiplied by drawn factors,
    /// at every execution or once per session (default none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub body_numbers: Vec<BodyNoise>,
}

/// The factors `1 + x` of one free body's physical numbers (a dynamic
/// body that is no joint's child), drawn anew at every execution or once
/// per session (`per`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyNoise {
    /// The body, by name.
    pub body: String,
    /// When the factors are drawn (default [`Per::Execution`]).
    #[serde(default, skip_serializing_if = "Per::is_execution")]
    pub per: Per,
    /// Its mass (the factor stays above 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<Spread>,
    /// Its linear damping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear_damping: Option<Spread>,
    /// Its angular damping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular_damping: Option<Spread>,
    /// Its friction coefficient.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<Spread>,
}

impl BodyNoise {
    /// The spreads in draw order: mass, linear and angular damping,
    /// friction, with their field names.
    pub fn spreads(&self) -> [(&'static str, Option<Spread>); 4] {
        [
            ("mass", self.mass),
            ("linear_damping", self.linear_damping),
            ("angular_damping", self.angular_damping),
            ("friction", self.friction),
        ]
    }
}

/// When a body's numbers are drawn.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Per {
    /// Anew at every execution, from the execution's key
    /// ([`DrawKey::execution`]).
    #[default]
    Execution,
    /// Once per session: every execution of a session draws the same
    /// factors, from the session's key ([`DrawKey::session`]); sessions of
    /// other seeds draw others.
    Session,
}

impl Per {
    /// Whether this is the default, [`Per::Execution`].
    pub fn is_execution(&self) -> bool {
        *self == Per::Execution
    }
}

/// The offsets of one start: a free body's (a dynamic body that is no
/// joint's child), added to its position and angle, or a joint's, added
/// to its coordinate (the bodies it carries follow). Give `body` or
/// `joint`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartNoise {
    /// The body, by name (empty for a joint).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub body: String,
    /// The joint, by name (empty for a body).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub joint: String,
    /// A body's: added to x, then to y, each drawn apart, in metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<Spread>,
    /// Added to a body's angle (rad), or to a joint's coordinate (rad for
    /// a hinge, m for a slider).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle: Option<Spread>,
}

/// How a number is drawn around 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Spread {
    /// A normal law of standard deviation `sd`, cut at 3 `sd` (a draw
    /// beyond is clamped there): every draw stays within known bounds.
    Gaussian {
        /// The standard deviation, >= 0.
        sd: f64,
    },
    /// Uniform in `[-half_width, half_width]`.
    Uniform {
        /// Half the width of the interval, >= 0.
        half_width: f64,
    },
}

impl Spread {
    /// The largest magnitude a draw can take (3 `sd`, or `half_width`).
    pub fn reach(self) -> f64 {
        match self {
            Spread::Gaussian { sd } => 3.0 * sd,
            Spread::Uniform { half_width } => half_width,
        }
    }

    /// One draw: a Gaussian takes two uniform numbers (Box-Muller), a
    /// uniform one.
    pub fn draw(self, rng: &mut SessionRng) -> f64 {
        match self {
            Spread::Gaussian { sd } => {
                let u: f64 = 1.0 - rng.random::<f64>(); // in (0, 1]
                let v: f64 = rng.random();
                let z = (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos();
                (z * sd).clamp(-3.0 * sd, 3.0 * sd)
            }
            Spread::Uniform { half_width } => half_width * (2.0 * rng.random::<f64>() - 1.0),
        }
    }
}

impl NoiseSpec {
    /// Whether the section draws anything at all.
    pub fn is_active(&self) -> bool {
        self.actions.is_some_and(|s| s.reach() > 0.0)
            || self.starts.iter().any(|s| {
                [s.position, s.angle]
                    .iter()
                    .flatten()
                    .any(|p| p.reach() > 0.0)
            })
            || (self.body_numbers.iter()).any(|b| {
                b.spreads()
                    .iter()
                    .any(|(_, p)| p.is_some_and(|p| p.reach() > 0.0))
            })
    }
}

/// The keys of one execution's draws: its session's, from which the body
/// numbers drawn [`Per::Session`] come (the same for every execution of a
/// session), and its own, from which every other draw comes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DrawKey {
    /// The session's key ([`session_key`] of its seed).
    pub session: u64,
    /// The execution's key ([`draw_key`] of the seed and the trial).
    pub execution: u64,
}

impl DrawKey {
    /// The keys of trial `trial` of the session seeded `seed`:
    /// `session_key(seed)` and `draw_key(seed, trial)`.
    ///
    /// ```
    /// use e3d::scene::physics::{draw_key, session_key, DrawKey};
    /// let k = DrawKey::trial(7, 3);
    /// assert_eq!((k.session, k.execution), (session_key(7), draw_key(7, 3)));
    /// assert_eq!(DrawKey::trial(7, 4).session, k.session);
    /// ```
    pub fn trial(seed: u64, trial: u64) -> DrawKey {
        DrawKey {
            session: session_key(seed),
            execution: draw_key(seed, trial),
        }
    }
}

/// The key of the draws made once per session of seed `seed`:
/// `draw_key(seed, u64::MAX - 1)`, a trial no session reaches.
pub fn session_key(seed: u64) -> u64 {
    draw_key(seed, u64::MAX - 1)
}

/// The key of the draws of one execution: trial `trial` of the session
/// seeded `seed` (or, for `scene exec --repeat`, run `trial` of a list of
/// commands, then the command's index: `draw_key(draw_key(seed, run),
/// index)`). A SplitMix64 mix of both: neighbouring seeds and trials give
/// unrelated generators.
pub fn draw_key(seed: u64, trial: u64) -> u64 {
    let mix = |mut z: u64| {
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    mix(mix(seed.wrapping_add(0x9e37_79b9_7f4a_7c15)) ^ trial)
}

/// Why a noisy scene refuses `what` (an outcome table, a memo): the
/// message names the scene's `noise` section.
pub fn noise_refusal(scene: &str, what: &str) -> String {
    format!(
        "scene `{scene}` has a `noise` section: each execution of a command draws its own noise, so {what} (one outcome per command) cannot stand for its executions; noisy commands run live (drop the table cache or the forced strategy)"
    )
}

/// The generator of the draws of the execution keyed `key`.
pub(crate) fn generator(key: u64) -> SessionRng {
    SessionRng::seed_from_u64(key)
}
