//! The bodies, joints, geoms, inertials, sites and contact pairs of an
//! MJCF model read into e3d's bodies and joints.

use super::{round, to_world, Reader, Site, R, SUPPORTED};
use crate::scene::mjcf::export::MassProps;
use crate::scene::physics::{BodyKind, BodySpec, JointKind, JointSpec, ShapeSpec};
use roxmltree::Node;

impl Reader<'_, '_> {
    pub(super) fn add_body(
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
    pub(super) fn body(&mut self, n: Node<'_, '_>, parent: Option<usize>) -> R<()> {
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
    pub(super) fn free_joints(
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
    pub(super) fn free_damping(&mut self, joints: &[Node<'_, '_>], i: usize) -> R<()> {
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
    pub(super) fn joint(
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

    pub(super) fn geom(&mut self, g: Node<'_, '_>, i: usize) -> R<()> {
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

    pub(super) fn inertial(&mut self, c: Node<'_, '_>, i: usize) -> R<()> {
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

    pub(super) fn site(&mut self, s: Node<'_, '_>, body: Option<usize>) -> R<()> {
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

    pub(super) fn contact(&mut self, n: Node<'_, '_>) -> R<()> {
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
}
