//! The planar subset of MJCF read into a scene (`e3d scene import`):
//! bodies in the x-y plane, hinges about z and slides in the plane,
//! sphere, box and capsule geoms, `inertial`, joint `damping`, `range` and
//! `armature`, `motor` and `position` actuators. Anything else is refused
//! with its line and column. This module walks the XML (the file, its
//! options, `<custom>`, `<worldbody>`); `bodies` reads the bodies,
//! joints, geoms and contact pairs, `actuators` the actuators into slots
//! and the scene they make.

use super::DRAG;
use crate::scene::physics::{BodyKind, BodySpec, DragSpec, JointSpec};
use crate::scene::{SceneSpec, SlotSpec};
use roxmltree::Node;
use std::fmt;

mod actuators;
mod bodies;

/// An MJCF file that e3d does not read: where, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfError {
    /// The file.
    pub file: String,
    /// The line (from 1).
    pub line: u32,
    /// The column (from 1).
    pub column: u32,
    /// What is wrong and what is supported.
    pub message: String,
}

impl fmt::Display for MjcfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.file, self.line, self.column, self.message
        )
    }
}

impl std::error::Error for MjcfError {}

/// A scene read from MJCF, and what did not map exactly (written as
/// comments above the scene by [`Imported::to_ron`]).
#[derive(Debug, Clone)]
pub struct Imported {
    /// The scene (valid: it loads).
    pub spec: SceneSpec,
    /// What was approximated or left out, one sentence each.
    pub notes: Vec<String>,
}

impl Imported {
    /// The scene as RON, the notes as `//` comments above it.
    pub fn to_ron(&self, source: &str) -> String {
        let mut out = format!(
            "// {}: imported from {source} by `e3d scene import`; edit it freely.\n",
            self.spec.name
        );
        out.push_str(
            "// One slot per actuator and round (`-`, `0`, `+`: the ends of its ctrlrange\n\
             // and nothing); the effect is the tracked point's cell on a 10 x 10 grid.\n",
        );
        for n in &self.notes {
            out.push_str("// - ");
            out.push_str(&n.replace('\n', " "));
            out.push('\n');
        }
        out.push_str(&self.spec.to_ron());
        out
    }
}

/// What `e3d scene import` reads, for the refusals.
const SUPPORTED: &str = "e3d reads the planar subset of MJCF: <compiler>, <option>, <worldbody> with <body> (pos, euler or quat about z), <joint> (hinge about z, slide in the x-y plane; range, damping, armature), <inertial>, <geom> (sphere, box, capsule with fromto), <site>, and <actuator> <motor> and <position> (gear, ctrlrange), <contact> <pair>, <custom>";

/// The slots per actuator of an imported scene (one round: every actuator
/// once).
const ROUNDS: usize = 3;

/// Reads the MJCF `text` (named `file` in errors) into a scene.
pub fn from_mjcf(text: &str, file: &str) -> Result<Imported, MjcfError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        let p = e.pos();
        MjcfError {
            file: file.into(),
            line: p.row,
            column: p.col,
            message: format!("not XML: {e}"),
        }
    })?;
    let mut r = Reader {
        doc: &doc,
        file,
        degrees: true,
        bodies: Vec::new(),
        frames: Vec::new(),
        joints: Vec::new(),
        notes: Vec::new(),
        sites: Vec::new(),
        timestep: 0.002,
        gravity: (0.0, 0.0),
        schedule: None,
        slots: Vec::new(),
        drags: Vec::new(),
    };
    r.read()?;
    let spec = r.scene(file)?;
    Ok(Imported {
        spec,
        notes: r.notes,
    })
}

/// A site: its body, its point in the body's frame, its name.
struct Site {
    body: usize,
    point: (f64, f64),
    name: String,
}

struct Reader<'a, 'i> {
    doc: &'a roxmltree::Document<'i>,
    file: &'a str,
    /// Angles in degrees (MJCF's default) or radians.
    degrees: bool,
    bodies: Vec<BodySpec>,
    /// Per body: its world pose and whether it moves.
    frames: Vec<((f64, f64), f64, bool)>,
    joints: Vec<JointSpec>,
    notes: Vec<String>,
    sites: Vec<Site>,
    timestep: f64,
    gravity: (f64, f64),
    /// From `e3d_schedule`: together, steps per phase, after, substeps.
    schedule: Option<Vec<f64>>,
    /// One per actuator with a control range: its name and alphabet.
    slots: Vec<SlotSpec>,
    /// From `e3d_drag_<body>`: the body, its drag, and the error if
    /// there is no such moving body.
    drags: Vec<(String, DragSpec, MjcfError)>,
}

type R<T> = Result<T, MjcfError>;

impl Reader<'_, '_> {
    fn error(&self, node: Node<'_, '_>, message: impl Into<String>) -> MjcfError {
        let p = self.doc.text_pos_at(node.range().start);
        MjcfError {
            file: self.file.into(),
            line: p.row,
            column: p.col,
            message: message.into(),
        }
    }

    /// Refuses an attribute of `node` not in `known`; `ignored` are read
    /// and left out (looks, contact tuning).
    fn attributes(&self, node: Node<'_, '_>, known: &[&str], ignored: &[&str]) -> R<()> {
        for a in node.attributes() {
            if !known.contains(&a.name()) && !ignored.contains(&a.name()) {
                let mut all: Vec<&str> = known.to_vec();
                all.extend(ignored);
                return Err(self.error(
                    node,
                    format!(
                        "<{} {}=...> is outside the planar subset: <{}> takes {}",
                        node.tag_name().name(),
                        a.name(),
                        node.tag_name().name(),
                        all.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    fn numbers(&self, node: Node<'_, '_>, name: &str) -> R<Option<Vec<f64>>> {
        let Some(text) = node.attribute(name) else {
            return Ok(None);
        };
        text.split_whitespace()
            .map(|t| t.parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect::<Option<Vec<f64>>>()
            .map(Some)
            .ok_or_else(|| self.error(node, format!("{name}=\"{text}\": expected numbers")))
    }

    fn exact(&self, node: Node<'_, '_>, name: &str, n: usize) -> R<Option<Vec<f64>>> {
        match self.numbers(node, name)? {
            Some(v) if v.len() != n => Err(self.error(
                node,
                format!("{name}: expected {n} numbers, found {}", v.len()),
            )),
            v => Ok(v),
        }
    }

    fn number(&self, node: Node<'_, '_>, name: &str) -> R<Option<f64>> {
        Ok(self.exact(node, name, 1)?.map(|v| v[0]))
    }

    fn angle(&self, x: f64) -> f64 {
        if self.degrees {
            x.to_radians()
        } else {
            x
        }
    }

    /// A position in the plane (`pos`, z must be 0).
    fn pos(&self, node: Node<'_, '_>) -> R<(f64, f64)> {
        match self.exact(node, "pos", 3)? {
            None => Ok((0.0, 0.0)),
            Some(v) if v[2] == 0.0 => Ok((v[0], v[1])),
            Some(_) => Err(self.error(node, "pos: z must be 0 (the scene's plane is x-y)")),
        }
    }

    /// A rotation about z (`euler` or `quat`; none: 0).
    fn rotation(&self, node: Node<'_, '_>) -> R<f64> {
        let off_plane = || {
            self.error(
                node,
                "only rotations about z are in the plane: euler=\"0 0 a\" or quat=\"w 0 0 z\"",
            )
        };
        if let Some(e) = self.exact(node, "euler", 3)? {
            if e[0] != 0.0 || e[1] != 0.0 {
                return Err(off_plane());
            }
            return Ok(self.angle(e[2]));
        }
        if let Some(q) = self.exact(node, "quat", 4)? {
            if q[1] != 0.0 || q[2] != 0.0 {
                return Err(off_plane());
            }
            return Ok(2.0 * q[3].atan2(q[0]));
        }
        for a in ["axisangle", "xyaxes", "zaxis"] {
            if node.attribute(a).is_some() {
                return Err(self.error(node, format!("{a}: write the rotation as euler=\"0 0 a\"")));
            }
        }
        Ok(0.0)
    }

    fn read(&mut self) -> R<()> {
        let root = self.doc.root_element();
        if root.tag_name().name() != "mujoco" {
            return Err(self.error(
                root,
                format!("expected <mujoco>, found <{}>", root.tag_name().name()),
            ));
        }
        self.attributes(root, &["model"], &[])?;
        let elements: Vec<Node<'_, '_>> = root.children().filter(|n| n.is_element()).collect();
        // the compiler first: it says how angles are written
        for n in &elements {
            if n.tag_name().name() == "custom" {
                self.custom(*n)?;
            }
            if n.tag_name().name() == "compiler" {
                self.attributes(
                    *n,
                    &["angle"],
                    &["inertiafromgeom", "autolimits", "coordinate"],
                )?;
                self.degrees = match n.attribute("angle") {
                    None | Some("degree") => true,
                    Some("radian") => false,
                    Some(a) => {
                        return Err(
                            self.error(*n, format!("angle=\"{a}\": expected radian or degree"))
                        )
                    }
                };
            }
        }
        for n in &elements {
            match n.tag_name().name() {
                "option" => self.option(*n)?,
                "worldbody" => self.worldbody(*n)?,
                "contact" => self.contact(*n)?,
                "compiler" | "custom" => {}
                "actuator" => {}
                other => {
                    return Err(self.error(
                        *n,
                        format!("<{other}> is outside the planar subset. {SUPPORTED}"),
                    ))
                }
            }
        }
        for n in &elements {
            if n.tag_name().name() == "actuator" {
                self.actuators(*n)?;
            }
        }
        for (body, drag, unknown) in std::mem::take(&mut self.drags) {
            match self.bodies.iter_mut().find(|b| b.name == body) {
                Some(b) if b.kind == BodyKind::Dynamic => b.drag = Some(drag),
                _ => return Err(unknown),
            }
        }
        Ok(())
    }

    fn option(&mut self, n: Node<'_, '_>) -> R<()> {
        self.attributes(
            n,
            &["timestep", "gravity"],
            &["integrator", "iterations", "solver", "tolerance"],
        )?;
        no_children(self, n)?;
        if let Some(t) = self.number(n, "timestep")? {
            if t <= 0.0 {
                return Err(self.error(n, "timestep: expected a positive number"));
            }
            self.timestep = t;
        }
        if let Some(g) = self.exact(n, "gravity", 3)? {
            self.gravity = (g[0], g[1]);
            if g[2] != 0.0 {
                self.notes.push(format!(
                    "gravity's z component ({}) acts across the plane and is left out",
                    g[2]
                ));
            }
        }
        Ok(())
    }

    fn custom(&mut self, n: Node<'_, '_>) -> R<()> {
        for c in n.children().filter(|c| c.is_element()) {
            if let Some(body) = c
                .attribute("name")
                .and_then(|name| name.strip_prefix(DRAG))
                .filter(|_| c.tag_name().name() == "numeric")
            {
                let v = self.numbers(c, "data")?.unwrap_or_default();
                let [along, across, turn] = v[..] else {
                    return Err(self.error(
                        c,
                        format!("{DRAG}{body}: expected 3 numbers (along, across, turn)"),
                    ));
                };
                let unknown = self.error(c, format!("{DRAG}{body}: the drag of a moving body, but there is no moving body `{body}`"));
                self.drags.push((
                    body.to_string(),
                    DragSpec {
                        along,
                        across,
                        turn,
                    },
                    unknown,
                ));
            }
            if c.tag_name().name() == "numeric" && c.attribute("name") == Some("e3d_schedule") {
                let v = self.numbers(c, "data")?.unwrap_or_default();
                if v.len() != 4 {
                    return Err(self.error(c, "e3d_schedule: expected 4 numbers (together, steps per phase, steps after, substeps)"));
                }
                self.schedule = Some(v);
            }
        }
        Ok(())
    }

    fn worldbody(&mut self, n: Node<'_, '_>) -> R<()> {
        self.attributes(n, &[], &[])?;
        for c in n.children().filter(|c| c.is_element()) {
            match c.tag_name().name() {
                "body" => self.body(c, None)?,
                "geom" => {
                    // a geom of the world: a fixed body
                    let i = self.bodies.len();
                    let name = c
                        .attribute("name")
                        .map_or(format!("world{i}"), str::to_string);
                    self.add_body(c, name, ((0.0, 0.0), 0.0), false)?;
                    self.geom(c, i)?;
                }
                "site" => self.site(c, None)?,
                "light" | "camera" => {}
                other => {
                    return Err(self.error(
                        c,
                        format!("<{other}> is outside the planar subset. {SUPPORTED}"),
                    ))
                }
            }
        }
        Ok(())
    }
}

fn no_children(r: &Reader<'_, '_>, n: Node<'_, '_>) -> R<()> {
    match n.children().find(|c| c.is_element()) {
        Some(c) => Err(r.error(
            c,
            format!(
                "<{}> inside <{}> is outside the planar subset",
                c.tag_name().name(),
                n.tag_name().name()
            ),
        )),
        None => Ok(()),
    }
}

/// Local point `p` of a frame at `pos`, turned `angle`, in the world.
fn to_world(pos: (f64, f64), angle: f64, p: (f64, f64)) -> (f64, f64) {
    crate::scene::physics::to_world_point(pos, angle, p)
}

/// A point with the rounding noise of a rotation taken off (1e-12 m).
fn round(p: (f64, f64)) -> (f64, f64) {
    let r = |x: f64| (x * 1e12).round() / 1e12;
    (r(p.0), r(p.1))
}
