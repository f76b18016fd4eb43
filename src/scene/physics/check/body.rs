//! The checks of one body: its name, shape, mass, start pose and
//! material.

use super::{check_name, finite2, quoted};
use crate::scene::physics::limits::*;
use crate::scene::physics::{BodyKind, BodySpec, PhysicsSpec, ShapeSpec};
use crate::scene::Invalid;

impl PhysicsSpec {
    /// One body: its name (not `ground`, not a duplicate), shape, mass,
    /// start pose and material.
    pub(super) fn validate_body(&self, b: &BodySpec, duplicate: bool) -> Result<(), Invalid> {
        let (at, who) = check_name("body", &b.name, duplicate)?;
        let on = On::new(Some(&at), &who);
        check_shape(b, on)?;
        check_mass(b, on)?;
        check_pose_and_material(b, on)?;
        check_inertia_and_drag(b, self.dt, on)
    }

    /// Refuses a body field that would do nothing on this kind of body
    /// (`docs/physics.md`): damping or `lock_rotation` on a fixed or kinematic
    /// body, or on a multibody link (a chain hung on `ground`); `drag` or
    /// `inertia` on a fixed or kinematic body.
    pub(super) fn check_body_kind(&self, b: &BodySpec) -> Result<(), Invalid> {
        let at = quoted(&b.name);
        let (kind, instead) = if b.kind != BodyKind::Dynamic {
            (
                format!("`{}` is {:?}: it never moves", b.name, b.kind),
                "remove the field (or make the body Dynamic)",
            )
        } else if self.hangs_from_ground(&b.name) {
            (
                format!(
                    "`{}` is a link of a chain hung on `ground` (a Rapier multibody link, which ignores a body's own damping and rotation lock)",
                    b.name
                ),
                "damp its joint instead (`damping` on the joint, per degree of freedom; for `lock_rotation`: hold the joint with `limits` or a `motor`), or hang the chain on a dynamic body (a free-floating chain, whose links take this field)",
            )
        } else {
            return Ok(());
        };
        // drag and inertia act on a link too: refused on fixed and
        // kinematic bodies only
        let never_moves = b.kind != BodyKind::Dynamic;
        let fields = [
            ("drag", never_moves && b.drag.is_some()),
            ("inertia", never_moves && b.inertia.is_some()),
            ("linear_damping", b.linear_damping != 0.0),
            ("angular_damping", b.angular_damping != 0.0),
            ("lock_rotation", b.lock_rotation),
        ];
        if let Some((field, _)) = fields.into_iter().find(|&(_, set)| set) {
            return Err(Invalid::at(
                field,
                Some(&at),
                &format!(
                    "body `{}`: no `{field}` here, because {kind}; {instead}",
                    b.name
                ),
            ));
        }
        Ok(())
    }
}

/// A body's shape: finite, sizes > 0 within [`MIN_SIZE`] and
/// [`MAX_LENGTH`], coordinates within [`MAX_LENGTH`].
fn check_shape(b: &BodySpec, on: On) -> Result<(), Invalid> {
    if !b.shape.numbers().iter().all(|v| v.is_finite()) {
        return Err(on.bad("shape", "finite numbers in its shape"));
    }
    let found = |field, what: String| Err(on.bad(field, what));
    match &b.shape {
        ShapeSpec::Ball { radius } | ShapeSpec::Capsule { radius, .. } if *radius <= 0.0 => {
            return found("radius", format!("a radius > 0, found {radius}"));
        }
        ShapeSpec::Cuboid { width, height } if *width <= 0.0 || *height <= 0.0 => {
            return found(
                "shape",
                format!("a width and height > 0, found {width} x {height}"),
            );
        }
        ShapeSpec::Segment { a, b: e } if a == e => {
            return found("shape", "a segment of two distinct points".into());
        }
        ShapeSpec::Polyline { points } if points.len() < 2 => {
            return found("points", "at least two points".into());
        }
        ShapeSpec::Polyline { points } if points.len() > MAX_POINTS => {
            let n = points.len();
            return found("points", format!("at most {MAX_POINTS} points, found {n}"));
        }
        _ => {}
    }
    // what f32 can hold: sizes, then every coordinate
    let sizes: Vec<(&str, f64)> = match &b.shape {
        ShapeSpec::Ball { radius } | ShapeSpec::Capsule { radius, .. } => {
            vec![("radius", *radius)]
        }
        ShapeSpec::Cuboid { width, height } => vec![("width", *width), ("height", *height)],
        _ => Vec::new(),
    };
    for (f, v) in sizes {
        on.number(f, f, v, Bound::range(MIN_SIZE, MAX_LENGTH, "m"))?;
    }
    for v in b.shape.numbers() {
        on.number("shape", "coordinates", v, COORDINATES)?;
    }
    Ok(())
}

/// A body's `mass` or `density`: one of them, > 0, within bounds; a
/// dynamic body's mass from either, and an area if it rotates.
fn check_mass(b: &BodySpec, on: On) -> Result<(), Invalid> {
    if b.mass.is_some() && b.density.is_some() {
        return Err(on.bad("mass", "`mass` or `density`, not both"));
    }
    if let Some(m) = b.mass.filter(|m| !(m.is_finite() && *m > 0.0)) {
        return Err(on.bad("mass", format!("a mass > 0 in kg, found {m}")));
    }
    if let Some(d) = b.density {
        if !(d.is_finite() && d > 0.0) {
            return Err(on.bad("density", format!("a density > 0 in kg/m², found {d}")));
        }
        let bound = Bound::range(MIN_DENSITY, MAX_DENSITY, "kg/m²");
        on.number("density", "a density", d, bound)?;
    }
    if let Some(m) = b.mass {
        on.number("mass", "a mass", m, Bound::range(MIN_MASS, MAX_MASS, "kg"))?;
    }
    if b.kind == BodyKind::Dynamic {
        check_dynamic_mass(b, on)?;
    }
    Ok(())
}

/// A body's start pose, dampings, friction and restitution.
fn check_pose_and_material(b: &BodySpec, on: On) -> Result<(), Invalid> {
    if !finite2(b.position) || !b.angle.is_finite() {
        return Err(on.bad("position", "a finite start pose"));
    }
    for v in [b.position.0, b.position.1] {
        on.number("position", "coordinates", v, COORDINATES)?;
    }
    let angles = Bound::magnitude(MAX_ANGLE, "rad");
    on.number("angle", "an angle", b.angle, angles)?;
    for (f, v, hi) in [
        ("linear_damping", b.linear_damping, MAX_COEFFICIENT),
        ("angular_damping", b.angular_damping, MAX_COEFFICIENT),
        ("friction", b.friction, MAX_FRICTION),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(on.bad(f, format!("a finite number >= 0, found {v}")));
        }
        on.number(f, "a number", v, Bound::range(0.0, hi, ""))?;
    }
    if !(in_range(b.restitution, 0.0, 1.0, false)) {
        let r = b.restitution;
        return Err(on.bad("restitution", format!("a restitution in [0, 1], found {r}")));
    }
    Ok(())
}

/// A body's `inertia` (> 0, on a shape with an area) and `drag`
/// (coefficients >= 0, weak enough that one explicit step of `dt` never
/// reverses the velocity it acts on: `across x dt / mass <= 1`, the same
/// for `along`, and `turn x dt / inertia <= 1`).
fn check_inertia_and_drag(b: &BodySpec, dt: f64, on: On) -> Result<(), Invalid> {
    if let Some(i) = b.inertia {
        if !(i.is_finite() && i > 0.0) {
            return Err(on.bad("inertia", format!("an inertia > 0 in kg·m², found {i}")));
        }
        on.number(
            "inertia",
            "an inertia",
            i,
            Bound::range(MIN_MASS * MIN_SIZE * MIN_SIZE, MAX_MASS, "kg·m²"),
        )?;
        if b.shape.area() <= 0.0 {
            return Err(on.bad(
                "inertia",
                "no `inertia` on a segment or polyline (it has no area, so it does not rotate)",
            ));
        }
    }
    let Some(d) = b.drag else { return Ok(()) };
    let (m, i) = (b.mass_kg(), b.inertia_kg_m2());
    for (f, v, of) in [
        ("along", d.along, Some(m)),
        ("across", d.across, Some(m)),
        ("turn", d.turn, i),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(on.bad(f, format!("a finite drag >= 0, found {v}")));
        }
        on.number(f, "a drag", v, Bound::range(0.0, MAX_COEFFICIENT, ""))?;
        if let Some(of) = of.filter(|&of| v * dt > of) {
            let what = if f == "turn" { "inertia" } else { "mass" };
            return Err(on.bad(
                f,
                format!(
                    "a drag of at most {what} / dt = {:.4} (one step of {dt} s would reverse the motion), found {v}",
                    of / dt
                ),
            ));
        }
    }
    Ok(())
}

/// A dynamic body's mass (its own, or density x area): > 0, within
/// bounds, and a shape with an area unless it does not rotate.
fn check_dynamic_mass(b: &BodySpec, on: On) -> Result<(), Invalid> {
    if b.shape.area() <= 0.0 && b.mass.is_none() {
        return Err(on.bad(
            "mass",
            "a `mass` (a dynamic segment or polyline has no area, so no mass from its density)",
        ));
    }
    if b.mass_kg().is_nan() || b.mass_kg() <= 0.0 {
        return Err(on.bad("mass", "a mass > 0"));
    }
    let field = if b.density.is_some() {
        "density"
    } else {
        "shape"
    };
    let masses = Bound::range(MIN_MASS, MAX_MASS, "kg");
    on.number(field, "a mass (density x area)", b.mass_kg(), masses)?;
    if b.shape.area() <= 0.0 && !b.lock_rotation {
        return Err(on.bad(
            "shape",
            "a shape with an area (Ball, Cuboid, Capsule) for a dynamic body that rotates",
        ));
    }
    Ok(())
}
