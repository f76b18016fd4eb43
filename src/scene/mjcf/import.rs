//! The planar subset of MJCF read into a scene (`e3d scene import`):
//! bodies in the x-y plane, hinges about z and slides in the plane,
//! sphere, box and capsule geoms, `inertial`, joint `damping`, `range` and
//! `armature`, `motor` and `position` actuators. Anything else is refused
//! with its line and column.

use super::export::MassProps;
use super::{COM_SITE, EFFECT_SITE, ORIGIN_SITE};
use crate::effect::EffectGrid;
use crate::scene::physics::{
    BodyKind, BodySpec, EffectSpec, JointKind, JointSpec, MotorSpec, PhysicsSpec, Schedule,
    ShapeSpec,
};
use crate::scene::{Action, CommandSpec, RewardSpec, SceneSpec, SlotSpec, SymbolSpec, WorldSpec};
use roxmltree::Node;
use std::fmt;

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

    fn add_body(
        &mut self,
        n: Node<'_, '_>,
        name: String,
        pose: ((f64, f64), f64),
        moves: bool,
    ) -> R<()> {
        if self.bodies.iter().any(|b| b.name == name) || name == "ground" {
            return Err(self.error(
                n,
                format!(
                    "a second body named `{name}` (or `ground`): e3d's bodies need unique names"
                ),
            ));
        }
        self.bodies.push(BodySpec {
            name,
            kind: if moves {
                BodyKind::Dynamic
            } else {
                BodyKind::Fixed
            },
            shape: ShapeSpec::Ball { radius: 0.0 },
            mass: None,
            density: None,
            position: pose.0,
            angle: pose.1,
            linear_damping: 0.0,
            angular_damping: 0.0,
            friction: 1.0,
            restitution: 0.0,
            lock_rotation: false,
            collide: true,
            fast_rotation: false,
            drag: None,
            inertia: None,
        });
        self.frames.push((pose.0, pose.1, moves));
        Ok(())
    }

    /// A `<body>` (and its subtree) in body `parent` (`None`: the world).
    fn body(&mut self, n: Node<'_, '_>, parent: Option<usize>) -> R<()> {
        self.attributes(n, &["name", "pos", "euler", "quat"], &["childclass"])?;
        let i = self.bodies.len();
        let name = n
            .attribute("name")
            .map_or(format!("body{i}"), str::to_string);
        let (local, turn) = (self.pos(n)?, self.rotation(n)?);
        let (ppos, pangle, pmoves) = parent.map_or(((0.0, 0.0), 0.0, false), |p| self.frames[p]);
        let world = (to_world(ppos, pangle, local), pangle + turn);
        let joints: Vec<Node<'_, '_>> = n
            .children()
            .filter(|c| c.tag_name().name() == "joint")
            .collect();
        let planar_free = joints.len() >= 2;
        if joints.is_empty() && pmoves {
            return Err(self.error(n, "a body without a joint inside a moving body (welded): e3d's bodies are one shape each; give it a joint, or merge it into its parent"));
        }
        self.add_body(n, name.clone(), world, !joints.is_empty())?;
        if planar_free {
            self.free_joints(n, &joints, parent, i)?;
        } else if let Some(&j) = joints.first() {
            self.joint(j, parent, i, local, turn)?;
        }
        let mut inertial = None;
        let mut geom = None;
        for c in n.children().filter(|c| c.is_element()) {
            match c.tag_name().name() {
                "joint" | "body" => {}
                "inertial" => inertial = Some(c),
                "geom" if geom.is_some() => {
                    return Err(self.error(c, format!("a second geom in body `{name}`: an e3d body has one shape")))
                }
                "geom" => geom = Some(c),
                "site" => self.site(c, Some(i))?,
                "camera" | "light" => {}
                "freejoint" => {
                    return Err(self.error(c, "<freejoint> moves in 3D: for a free body in the plane write slide joints along x and y and a hinge about z"))
                }
                other => {
                    return Err(self.error(c, format!("<{other}> is outside the planar subset. {SUPPORTED}")))
                }
            }
        }
        let Some(g) = geom else {
            return Err(self.error(
                n,
                format!(
                    "body `{name}` has no geom: an e3d body has one shape (sphere, box or capsule)"
                ),
            ));
        };
        self.geom(g, i)?;
        if let Some(c) = inertial {
            self.inertial(c, i)?;
        }
        if self.bodies[i].kind == BodyKind::Dynamic && self.bodies[i].mass.is_none() {
            return Err(self.error(
                g,
                format!("body `{name}` has no mass: give <inertial mass=...> or the geom's mass"),
            ));
        }
        if planar_free {
            self.free_damping(&joints, i)?;
        }
        for c in n.children().filter(|c| c.tag_name().name() == "body") {
            self.body(c, Some(i))?;
        }
        Ok(())
    }

    /// The slides along x and y and the hinge about z of a free body.
    fn free_joints(
        &mut self,
        n: Node<'_, '_>,
        joints: &[Node<'_, '_>],
        parent: Option<usize>,
        i: usize,
    ) -> R<()> {
        let refuse = || {
            self.error(n, "several joints in one body: e3d reads one hinge or slide per body, or a free body in the plane (slide x, slide y, and optionally hinge z, in the world body)")
        };
        if parent.is_some() || joints.len() > 3 {
            return Err(refuse());
        }
        let mut kinds = Vec::new();
        for &j in joints {
            self.attributes(
                j,
                &["name", "type", "axis", "pos", "damping"],
                &["limited", "armature"],
            )?;
            let axis = self.exact(j, "axis", 3)?.unwrap_or(vec![0.0, 0.0, 1.0]);
            kinds.push((j.attribute("type").unwrap_or("hinge"), axis));
        }
        let is = |k: &(&str, Vec<f64>), t: &str, a: [f64; 3]| k.0 == t && k.1 == a;
        let ok = is(&kinds[0], "slide", [1.0, 0.0, 0.0])
            && is(&kinds[1], "slide", [0.0, 1.0, 0.0])
            && kinds.get(2).is_none_or(|k| is(k, "hinge", [0.0, 0.0, 1.0]));
        if !ok {
            return Err(refuse());
        }
        self.bodies[i].lock_rotation = kinds.len() == 2;
        Ok(())
    }

    /// A free body's joint damping as its body damping (c m, c I).
    fn free_damping(&mut self, joints: &[Node<'_, '_>], i: usize) -> R<()> {
        let mp = MassProps::of(&self.bodies[i]);
        let d: Vec<f64> = joints
            .iter()
            .map(|&j| self.number(j, "damping").map(|x| x.unwrap_or(0.0)))
            .collect::<R<_>>()?;
        if d[0] != d[1] {
            self.notes.push(format!(
                "body `{}`: the slides' damping differs ({} and {}); e3d's linear damping is one number, the mean",
                self.bodies[i].name, d[0], d[1]
            ));
        }
        let b = &mut self.bodies[i];
        b.linear_damping = (d[0] + d[1]) / 2.0 / mp.mass;
        if let Some(&w) = d.get(2) {
            if mp.inertia > 0.0 {
                b.angular_damping = w / mp.inertia;
            }
        }
        Ok(())
    }

    /// The joint of body `i` (at `local`, turned `turn` in its parent).
    fn joint(
        &mut self,
        j: Node<'_, '_>,
        parent: Option<usize>,
        i: usize,
        local: (f64, f64),
        turn: f64,
    ) -> R<()> {
        self.attributes(
            j,
            &[
                "name", "type", "pos", "axis", "range", "limited", "damping", "armature",
            ],
            &["solreflimit", "solimplimit", "margin", "group"],
        )?;
        for a in ["stiffness", "springref", "ref", "frictionloss"] {
            if j.attribute(a).is_some() {
                return Err(self.error(j, format!("joint {a} is not supported: e3d's joints have damping, limits and position motors")));
            }
        }
        let name = j
            .attribute("name")
            .map_or(format!("joint{}", self.joints.len()), str::to_string);
        let axis = self.exact(j, "axis", 3)?.unwrap_or(vec![0.0, 0.0, 1.0]);
        let anchor = self.pos(j)?;
        let hinge = match j.attribute("type").unwrap_or("hinge") {
            "hinge" => true,
            "slide" => false,
            t => {
                return Err(self.error(
                    j,
                    format!(
                        "joint type \"{t}\": e3d reads hinge (about z) and slide (in the plane)"
                    ),
                ))
            }
        };
        let n = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
        let kind = if hinge {
            if !(axis[0] == 0.0 && axis[1] == 0.0 && axis[2] > 0.0) {
                return Err(self.error(j, "a hinge turns about z in the plane: axis=\"0 0 1\""));
            }
            JointKind::Revolute
        } else {
            if axis[2] != 0.0 || n == 0.0 {
                return Err(self.error(j, "a slide moves in the plane: axis=\"x y 0\""));
            }
            // the axis in the parent's frame
            let (s, c) = turn.sin_cos();
            let (x, y) = (axis[0] / n, axis[1] / n);
            JointKind::Prismatic {
                axis: (c * x - s * y, s * x + c * y),
            }
        };
        let unit = |x: f64| if hinge { self.angle(x) } else { x };
        let limited = j.attribute("limited") != Some("false");
        let limits = match self.exact(j, "range", 2)? {
            Some(r) if limited => {
                if r[0] >= r[1] {
                    return Err(self.error(j, "range: expected min < max"));
                }
                Some((unit(r[0]), unit(r[1])))
            }
            _ => None,
        };
        if let Some(a) = self.number(j, "armature")?.filter(|a| *a != 0.0) {
            self.notes.push(format!(
                "joint `{name}`: armature {a} (a rotor's inertia on the joint) has no e3d counterpart and is left out"
            ));
        }
        // the anchor in the parent's frame (the world's for ground)
        let parent_anchor = to_world(local, turn, anchor);
        self.joints.push(JointSpec {
            name,
            parent: parent.map_or("ground".into(), |p| self.bodies[p].name.clone()),
            child: self.bodies[i].name.clone(),
            parent_anchor: round(parent_anchor),
            child_anchor: anchor,
            limits,
            damping: self.number(j, "damping")?.unwrap_or(0.0),
            motor: None,
            contacts: false,
            kind,
        });
        Ok(())
    }

    fn geom(&mut self, g: Node<'_, '_>, i: usize) -> R<()> {
        self.attributes(
            g,
            &[
                "type",
                "size",
                "fromto",
                "pos",
                "euler",
                "quat",
                "mass",
                "friction",
                "contype",
                "conaffinity",
                "name",
            ],
            &[
                "rgba", "solref", "solimp", "condim", "group", "material", "margin", "priority",
                "class",
            ],
        )?;
        if g.attribute("density").is_some() {
            return Err(self.error(
                g,
                "density is per volume in MJCF: give the geom's mass (or <inertial mass>)",
            ));
        }
        let size = self.numbers(g, "size")?.unwrap_or_default();
        let pos = self.pos(g)?;
        let turn = self.rotation(g)?;
        let size_at = |k: usize| {
            size.get(k).copied().filter(|s| *s > 0.0).ok_or_else(|| {
                self.error(
                    g,
                    format!("size: expected at least {} positive numbers", k + 1),
                )
            })
        };
        let centred = || {
            if pos != (0.0, 0.0) || turn != 0.0 {
                Err(self.error(g, "a sphere or box is centred on its body in e3d: move the body instead (pos and euler on <body>)"))
            } else {
                Ok(())
            }
        };
        let shape = match g.attribute("type").unwrap_or("sphere") {
            "sphere" => {
                centred()?;
                ShapeSpec::Ball {
                    radius: size_at(0)?,
                }
            }
            "box" => {
                centred()?;
                ShapeSpec::Cuboid {
                    width: 2.0 * size_at(0)?,
                    height: 2.0 * size_at(1)?,
                }
            }
            "capsule" => {
                let Some(f) = self.exact(g, "fromto", 6)? else {
                    return Err(
                        self.error(g, "a capsule needs fromto=\"x1 y1 0 x2 y2 0\" in the plane")
                    );
                };
                if f[2] != 0.0 || f[5] != 0.0 {
                    return Err(self.error(g, "fromto: z must be 0 (the scene's plane is x-y)"));
                }
                ShapeSpec::Capsule {
                    a: (f[0], f[1]),
                    b: (f[3], f[4]),
                    radius: size_at(0)?,
                }
            }
            t => {
                return Err(self.error(
                    g,
                    format!("geom type \"{t}\": e3d reads sphere, box and capsule"),
                ))
            }
        };
        let b = &mut self.bodies[i];
        b.shape = shape;
        if let Some(f) = self.numbers(g, "friction")? {
            if let Some(&f0) = f.first() {
                self.bodies[i].friction = f0;
            }
        }
        let zero = |a| g.attribute(a) == Some("0");
        if zero("contype") && zero("conaffinity") {
            self.bodies[i].collide = false;
        }
        if let Some(m) = self.number(g, "mass")? {
            if self.bodies[i].kind == BodyKind::Dynamic {
                self.bodies[i].mass = Some(m);
            }
        }
        Ok(())
    }

    fn inertial(&mut self, c: Node<'_, '_>, i: usize) -> R<()> {
        self.attributes(c, &["pos", "mass", "diaginertia"], &["euler", "quat"])?;
        if self.bodies[i].kind != BodyKind::Dynamic {
            return Ok(());
        }
        let Some(m) = self.number(c, "mass")?.filter(|m| *m > 0.0) else {
            return Err(self.error(c, "<inertial> needs a positive mass"));
        };
        self.bodies[i].mass = Some(m);
        let mp = MassProps::of(&self.bodies[i]);
        let com = self.pos(c)?;
        let name = self.bodies[i].name.clone();
        if (com.0 - mp.com.0).hypot(com.1 - mp.com.1) > 1e-6 {
            self.notes.push(format!(
                "body `{name}`: centre of mass ({}, {}) in the file, ({}, {}) in e3d (the shape's centroid)",
                com.0, com.1, mp.com.0, mp.com.1
            ));
        }
        if let Some(d) = self.exact(c, "diaginertia", 3)? {
            if (d[2] - mp.inertia).abs() > 1e-6 * d[2].abs().max(1e-9) {
                self.notes.push(format!(
                    "body `{name}`: inertia about z {} in the file, {:.6e} in e3d (the shape's at its mass)",
                    d[2], mp.inertia
                ));
            }
        }
        Ok(())
    }

    fn site(&mut self, s: Node<'_, '_>, body: Option<usize>) -> R<()> {
        self.attributes(
            s,
            &["name", "pos"],
            &["size", "rgba", "type", "group", "euler", "quat"],
        )?;
        let point = self.pos(s)?;
        if let Some(b) = body {
            self.sites.push(Site {
                body: b,
                point,
                name: s.attribute("name").unwrap_or("").into(),
            });
        }
        Ok(())
    }

    fn contact(&mut self, n: Node<'_, '_>) -> R<()> {
        for p in n.children().filter(|c| c.is_element()) {
            if p.tag_name().name() != "pair" {
                return Err(self.error(
                    p,
                    format!(
                        "<{}> in <contact>: e3d reads <pair geom1 geom2> between a joint's bodies",
                        p.tag_name().name()
                    ),
                ));
            }
            let geom_body = |a: &str| {
                let g = p.attribute(a).unwrap_or("");
                self.bodies
                    .iter()
                    .position(|b| b.name == g || g.starts_with(&format!("{}_", b.name)))
            };
            let (Some(a), Some(b)) = (geom_body("geom1"), geom_body("geom2")) else {
                return Err(self.error(p, "a pair's geoms must be named after their bodies"));
            };
            let (na, nb) = (self.bodies[a].name.clone(), self.bodies[b].name.clone());
            match self
                .joints
                .iter_mut()
                .find(|j| (j.parent == na && j.child == nb) || (j.parent == nb && j.child == na))
            {
                Some(j) => j.contacts = true,
                None => return Err(self.error(
                    p,
                    "a contact pair between bodies not joined to each other: they collide anyway",
                )),
            }
        }
        Ok(())
    }

    fn actuators(&mut self, n: Node<'_, '_>) -> R<()> {
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
    fn scene(&mut self, file: &str) -> R<SceneSpec> {
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
    fn effect(&mut self) -> EffectSpec {
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
