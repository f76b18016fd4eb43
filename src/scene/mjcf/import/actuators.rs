//! The actuators of an MJCF model read into slots and symbols, and the
//! scene they make with the bodies and joints read.

use super::{to_world, Reader, Site, R, ROUNDS};
use crate::effect::EffectGrid;
use crate::scene::mjcf::export::MassProps;
use crate::scene::mjcf::{COM_SITE, EFFECT_SITE, ORIGIN_SITE};
use crate::scene::physics::{BodyKind, EffectSpec, MotorSpec, PhysicsSpec, Schedule};
use crate::scene::{Action, CommandSpec, RewardSpec, SceneSpec, SlotSpec, SymbolSpec, WorldSpec};
use roxmltree::Node;

impl Reader<'_, '_> {
    pub(super) fn actuators(&mut self, n: Node<'_, '_>) -> R<()> {
        for a in n.children().filter(|c| c.is_element()) {
            let kind = a.tag_name().name();
            if kind != "motor" && kind != "position" {
                return Err(self.error(a, format!("<{kind}> actuators are outside the subset: e3d reads <motor> (joint or site) and <position> (joint)")));
            }
            self.attributes(
                a,
                &[
                    "name",
                    "joint",
                    "site",
                    "refsite",
                    "gear",
                    "ctrlrange",
                    "ctrllimited",
                    "kp",
                    "kv",
                ],
                &["forcerange", "forcelimited", "class", "group"],
            )?;
            let gear = self.numbers(a, "gear")?.unwrap_or(vec![1.0]);
            let range = self.exact(a, "ctrlrange", 2)?.filter(|r| r[0] < r[1]);
            let name = a.attribute("name").map(str::to_string);
            let joint = a.attribute("joint").map(|j| {
                self.joints
                    .iter()
                    .position(|s| s.name == j)
                    .ok_or_else(|| self.error(a, format!("joint `{j}`: no such hinge or slide (free bodies' slides cannot be driven; drive the body through a site)")))
            });
            let joint = joint.transpose()?;
            let act: Box<dyn Fn(f64) -> Action> = match (kind, joint, a.attribute("site")) {
                ("position", Some(k), _) => {
                    let g = gear[0];
                    let kp = self.number(a, "kp")?.unwrap_or(1.0);
                    let kv = self.number(a, "kv")?.unwrap_or(0.0);
                    // force = g (kp (ctrl - g q) - kv g qdot): a target of ctrl / g
                    self.joints[k].motor = Some(MotorSpec {
                        stiffness: kp * g * g,
                        damping: kv * g * g,
                    });
                    // a ctrlrange is never in degrees
                    let j = self.joints[k].name.clone();
                    Box::new(move |c| Action::Target {
                        joint: j.clone(),
                        angle: c / g,
                    })
                }
                ("motor", Some(k), _) => {
                    let g = gear[0];
                    let j = &self.joints[k];
                    match j.axis() {
                        None => {
                            let j = j.name.clone();
                            Box::new(move |c| Action::Torque { joint: j.clone(), torque: g * c })
                        }
                        Some((x, y)) if j.parent == "ground" => {
                            let body = j.child.clone();
                            Box::new(move |c| Action::Force { body: body.clone(), force: (g * c * x, g * c * y) })
                        }
                        Some(_) => return Err(self.error(a, "a motor on a slide whose parent moves: e3d pushes bodies with world-frame forces; drive the body through a site")),
                    }
                }
                ("motor", None, Some(site)) => {
                    if a.attribute("refsite").is_some_and(|r| r != ORIGIN_SITE) {
                        return Err(self.error(a, format!("refsite: e3d's forces are in the world frame: refsite=\"{ORIGIN_SITE}\" (a site at the world's origin) or none")));
                    }
                    let Some(s) = self.sites.iter().find(|s| s.name == site) else {
                        return Err(
                            self.error(a, format!("site `{site}`: no such site on a moving body"))
                        );
                    };
                    let mp = MassProps::of(&self.bodies[s.body]);
                    if (s.point.0 - mp.com.0).hypot(s.point.1 - mp.com.1) > 1e-6
                        || gear.len() != 6
                        || gear[2..].iter().any(|g| *g != 0.0)
                    {
                        return Err(self.error(a, "a force on a site: e3d pushes a body at its centre of mass along world x and y (gear=\"gx gy 0 0 0 0\", refsite at the origin)"));
                    }
                    let body = self.bodies[s.body].name.clone();
                    let (gx, gy) = (gear[0], gear[1]);
                    Box::new(move |c| Action::Force {
                        body: body.clone(),
                        force: (gx * c, gy * c),
                    })
                }
                _ => {
                    return Err(self.error(
                        a,
                        "an actuator needs a joint (motor, position) or a site (motor)",
                    ))
                }
            };
            let Some(r) = range else {
                if kind == "position" {
                    continue; // a motor holding its start pose, driven by no slot
                }
                return Err(self.error(
                    a,
                    "ctrlrange=\"min max\" (min < max) is needed: its ends are the slot's symbols",
                ));
            };
            let mut alphabet = Vec::new();
            for (symbol, c) in [('-', r[0]), ('0', 0.0), ('+', r[1])] {
                let action = if c == 0.0 { Action::Idle } else { act(c) };
                if c == 0.0 || (symbol == '-') == (c < 0.0) || r[0] >= 0.0 || r[1] <= 0.0 {
                    alphabet.push(SymbolSpec { symbol, action });
                }
            }
            alphabet.dedup_by(|x, y| x.action == y.action);
            self.slots.push(SlotSpec { name, alphabet });
        }
        Ok(())
    }

    /// The scene: the bodies and joints read, a schedule, slots and an
    /// effect.
    pub(super) fn scene(&mut self, file: &str) -> R<SceneSpec> {
        let root = self.doc.root_element();
        let name = root.attribute("model").map_or_else(
            || {
                std::path::Path::new(file)
                    .file_stem()
                    .map_or("imported".into(), |s| s.to_string_lossy().into_owned())
            },
            str::to_string,
        );
        if self.slots.is_empty() {
            return Err(self.error(root, "no actuator with a ctrlrange: an e3d scene needs at least one slot (a <motor> or <position> with ctrlrange)"));
        }
        let (dt, iterations, schedule, rounds) = match &self.schedule {
            Some(s) => {
                let sub = s[3].max(1.0);
                let dt = self.timestep * sub;
                let secs = |steps: f64| steps / sub * dt;
                let it = (sub != 4.0).then_some(sub as usize);
                if s[0] != 0.0 {
                    (
                        dt,
                        it,
                        Schedule::Simultaneous {
                            push: secs(s[1]),
                            settle: secs(s[2]),
                        },
                        1,
                    )
                } else {
                    (
                        dt,
                        it,
                        Schedule::Sequential {
                            phase: secs(s[1]),
                            settle: secs(s[2]),
                        },
                        ROUNDS,
                    )
                }
            }
            None => {
                // 0.5 s and 1 s, in whole steps
                let dt = 4.0 * self.timestep;
                let secs = |t: f64| (t / dt).round().max(1.0) * dt;
                let schedule = Schedule::Sequential {
                    phase: secs(0.5),
                    settle: secs(1.0),
                };
                (dt, None, schedule, ROUNDS)
            }
        };
        let slots: Vec<SlotSpec> = (0..rounds).flat_map(|_| self.slots.clone()).collect();
        let effect = self.effect();
        let world = PhysicsSpec {
            gravity: self.gravity,
            dt,
            solver_iterations: iterations,
            max_speed: 100.0,
            bodies: self.bodies.clone(),
            joints: self.joints.clone(),
            schedule,
            effect,
            chains: Vec::new(),
            walls: Vec::new(),
            symmetry: None,
            contexts: Vec::new(),
            noise: None,
        };
        let spec = SceneSpec {
            name,
            description: format!(
                "Imported from {}.",
                std::path::Path::new(file)
                    .file_name()
                    .map_or(file.into(), |f| f.to_string_lossy())
            ),
            world: WorldSpec::Physics(world),
            slots: None,
            command: CommandSpec::Slots(slots),
            reward: RewardSpec::default(),
        };
        if let Err(e) = spec.validate() {
            return Err(self.error(root, format!("the scene read does not validate: {e}")));
        }
        Ok(spec)
    }

    /// The tracked point: an `e3d_effect` site, else the last site on a
    /// moving body, else the last moving body's origin; its cell on a 10 x
    /// 10 grid over a square around the start that the moving bodies
    /// cannot leave... as far as their start extent shows.
    pub(super) fn effect(&mut self) -> EffectSpec {
        let moving = |s: &&Site| self.bodies[s.body].kind == BodyKind::Dynamic;
        let site = self
            .sites
            .iter()
            .find(|s| s.name.starts_with(EFFECT_SITE))
            .or_else(|| {
                self.sites
                    .iter()
                    .filter(moving)
                    .rfind(|s| !s.name.ends_with(COM_SITE))
            });
        let (body, point) = match site {
            Some(s) => (s.body, s.point),
            None => {
                let b = self
                    .bodies
                    .iter()
                    .rposition(|b| b.kind == BodyKind::Dynamic)
                    .unwrap_or(0);
                (b, (0.0, 0.0))
            }
        };
        let b = &self.bodies[body];
        let at = to_world(b.position, b.angle, point);
        // the centre: the anchor on ground of the tracked body's tree, else its start
        let mut centre = at;
        let mut name = b.name.clone();
        while let Some(j) = self.joints.iter().find(|j| j.child == name) {
            if j.parent == "ground" {
                centre = j.parent_anchor;
                break;
            }
            name = j.parent.clone();
        }
        let reach = (at.0 - centre.0).hypot(at.1 - centre.1);
        let half = ((reach * 1.05) / 0.05).ceil().max(1.0) * 0.05;
        self.notes.push(format!(
            "the effect: body `{}`'s point ({}, {}) on a 10 x 10 grid over {half} m around ({}, {}); edit `effect` to taste",
            b.name, point.0, point.1, centre.0, centre.1
        ));
        EffectSpec {
            body: b.name.clone(),
            point,
            grid: Some(EffectGrid {
                rows: 10,
                cols: 10,
                min: [centre.0 - half, centre.1 - half],
                max: [centre.0 + half, centre.1 + half],
            }),
            features: Vec::new(),
        }
    }
}
