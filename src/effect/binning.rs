//! Effects of several kinds: binning one point, numbers or any product of
//! features ([`Binning`]) onto an [`EffectGrid`]'s cells.

use super::*;

/// One feature of the terminal state an effect is made of, as a scene
/// file writes it in `effect: (features: [...])`: a point's cell, a
/// joint's coordinate, a body's angle or a centre of mass, each binned
/// on its own; several
/// features make their product (the object's cell by the hand's cell).
///
/// ```ron
/// effect: (features: [
///     Joint(joint: "hinge", bins: 9, range: (-0.9, 0.9)),      // rad (a slider: m)
///     Joint(joint: "slider", bins: 7, range: (-1.4, 1.4)),
/// ]),
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Feature {
    /// A point of a body, binned on a grid: in world coordinates, or in
    /// the frame of another body (`frame`): the object's position seen
    /// from the hand.
    Point {
        /// The body the point belongs to.
        body: String,
        /// The point in the body's local frame (default its origin).
        #[serde(default)]
        point: (f64, f64),
        /// The body whose frame the point is measured in (default none:
        /// world coordinates): `(x, y)` in that body's local frame, its
        /// origin at the body's position, its x axis along its angle.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        frame: Option<String>,
        /// The grid the point is binned on (row 0 at the top).
        grid: EffectGrid,
    },
    /// A joint's coordinate: a revolute joint's angle (rad) or a
    /// prismatic joint's position (m), 0 at the start pose, binned on
    /// `bins` equal bins over `range`.
    Joint {
        /// The joint's name.
        joint: String,
        /// The number of bins.
        bins: usize,
        /// `(min, max)`: values outside count in the nearest end bin.
        range: (f64, f64),
    },
    /// A body's angle in the world, radians counter-clockwise, wrapped
    /// to `[-pi, pi)`, binned on `bins` equal bins over `range`.
    Angle {
        /// The body's name.
        body: String,
        /// The number of bins.
        bins: usize,
        /// `(min, max)`: values outside count in the nearest end bin.
        range: (f64, f64),
    },
    /// The centre of mass of a set of dynamic bodies (a free chain's
    /// links, a robot and what it carries), in world coordinates, binned
    /// on a grid.
    Centre {
        /// The bodies, at least one (a free chain: its links).
        bodies: Vec<String>,
        /// The grid the centre is binned on (row 0 at the top).
        grid: EffectGrid,
    },
}

impl Feature {
    /// How the feature's values are binned.
    pub fn axis(&self) -> Axis {
        match self {
            Feature::Point { grid, .. } | Feature::Centre { grid, .. } => Axis::Plane(grid.clone()),
            Feature::Joint { bins, range, .. } | Feature::Angle { bins, range, .. } => Axis::Line {
                bins: *bins,
                min: range.0,
                max: range.1,
            },
        }
    }
}

/// How one feature is binned: a point on a grid, or a number on equal
/// bins.
#[derive(Debug, Clone, PartialEq)]
pub enum Axis {
    /// A point `(x, y)` on a grid of cells.
    Plane(EffectGrid),
    /// A number on `bins` equal bins over `[min, max]`; values outside in
    /// the nearest end bin.
    Line {
        /// The number of bins.
        bins: usize,
        /// The low end.
        min: f64,
        /// The high end.
        max: f64,
    },
}

impl Axis {
    /// The number of values the feature reads (2 for a point, 1 for a
    /// number).
    pub fn arity(&self) -> usize {
        match self {
            Axis::Plane(_) => 2,
            Axis::Line { .. } => 1,
        }
    }

    /// The axis as a grid: a line of `bins` is one row of `bins` cells
    /// over `[min, max] x [0, 1]`.
    fn grid(&self) -> Result<EffectGrid, EffectError> {
        match self {
            Axis::Plane(g) => {
                g.validate()?;
                Ok(g.clone())
            }
            Axis::Line { bins, min, max } => EffectGrid::new(1, *bins, [*min, 0.0], [*max, 1.0]),
        }
    }
}

/// How the features of a terminal state make an effect: every effect is
/// a cell `(row, col)` of a *layout* grid, `effect = row * cols + col`,
/// which reward cells, tables, reports and figures read as they read the
/// one grid of a tracked point.
///
/// - one point: its grid (the effect of today's scenes, bit for bit);
/// - one number: a strip of one row, `bins` columns over `[min, max]`;
/// - two numbers: a grid, the first down the rows (its largest value in
///   row 0, like y), the second across the columns;
/// - any other product: nested blocks, the first feature's cells the
///   largest blocks: cell `(r_1, c_1)` of the first, `(r_2, c_2)` of the
///   second, ... is layout row `(r_1 R_2 + r_2) R_3 + ...`, column
///   `(c_1 C_2 + c_2) C_3 + ...` (a number counting as one row of
///   `bins` columns); the layout grid then has cells 1 x 1 over
///   `[0, cols] x [0, rows]` (no unit).
///
/// ```
/// use e3d::effect::{Axis, Binning};
/// // a cart-pole: the pole's angle (9 bins) by the cart's position (7 bins)
/// let b = Binning::new(vec![
///     Axis::Line { bins: 9, min: -0.9, max: 0.9 },
///     Axis::Line { bins: 7, min: -1.4, max: 1.4 },
/// ]).unwrap();
/// assert_eq!((b.layout().rows, b.layout().cols), (9, 7));
/// // angle 0.85 (the top bin: row 0), position -1.3 (column 0)
/// assert_eq!(b.locate(&[0.85, -1.3]), ([-1.3, 0.85], 0));
/// assert_eq!(b.num_effects(), 63);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Binning {
    axes: Vec<Axis>,
    grids: Vec<EffectGrid>,
    layout: EffectGrid,
    shape: Shape,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    /// One feature: its own grid.
    Single,
    /// Two numbers: a grid of the two.
    Pair,
    /// Nested blocks.
    Nested,
}

impl Binning {
    /// The binning of the product of `axes` (at least one), whose number
    /// of effects is at most [`MAX_EFFECTS`].
    pub fn new(axes: Vec<Axis>) -> Result<Self, EffectError> {
        if axes.is_empty() {
            return Err(EffectError::NoEffects);
        }
        let grids = axes.iter().map(Axis::grid).collect::<Result<Vec<_>, _>>()?;
        let lines = axes.iter().all(|a| matches!(a, Axis::Line { .. }));
        let (layout, shape) = if grids.len() == 1 {
            (grids[0].clone(), Shape::Single)
        } else if lines && grids.len() == 2 {
            let (a, b) = (&grids[0], &grids[1]);
            let g = EffectGrid {
                rows: a.cols,
                cols: b.cols,
                min: [b.min[0], a.min[0]],
                max: [b.max[0], a.max[0]],
            };
            (g, Shape::Pair)
        } else {
            let (rows, cols) = (grids.iter()).fold((1usize, 1usize), |(r, c), g| {
                (r.saturating_mul(g.rows), c.saturating_mul(g.cols))
            });
            let g = EffectGrid {
                rows,
                cols,
                min: [0.0, 0.0],
                max: [cols as f64, rows as f64],
            };
            (g, Shape::Nested)
        };
        layout.validate()?;
        Ok(Binning {
            axes,
            grids,
            layout,
            shape,
        })
    }

    /// The binning of one point's grid (today's effect).
    pub fn point(grid: EffectGrid) -> Result<Self, EffectError> {
        Binning::new(vec![Axis::Plane(grid)])
    }

    /// The number of values [`locate`](Self::locate) reads: 2 per point,
    /// 1 per number.
    pub fn arity(&self) -> usize {
        self.axes.iter().map(Axis::arity).sum()
    }

    /// The layout grid: its cells are the effects.
    pub fn layout(&self) -> &EffectGrid {
        &self.layout
    }

    /// The number of effects.
    pub fn num_effects(&self) -> usize {
        self.layout.num_cells()
    }

    /// Whether the layout's coordinates are the features' own (one
    /// feature, or two numbers), rather than cell counts of nested blocks.
    pub fn has_units(&self) -> bool {
        self.shape != Shape::Nested
    }

    /// The point of the layout and the effect of the features' values
    /// (2 per point, 1 per number, in order): for one point the point
    /// itself and its cell; for one number `v`, `(v, 0.5)`; for two
    /// numbers `(a, b)`, `(b, a)`; for nested blocks the centre of the
    /// layout cell.
    ///
    /// # Panics
    /// When `values` does not hold [`arity`](Self::arity) values.
    pub fn locate(&self, values: &[f64]) -> ([f64; 2], usize) {
        assert_eq!(values.len(), self.arity(), "one value per coordinate");
        // a point, or a number at mid-height of its strip
        let point = |a: &Axis, at: usize| match a {
            Axis::Plane(_) => [values[at], values[at + 1]],
            Axis::Line { .. } => [values[at], 0.5],
        };
        match self.shape {
            Shape::Single => {
                let p = point(&self.axes[0], 0);
                (p, self.layout.effect_of(p))
            }
            Shape::Pair => {
                let p = [values[1], values[0]];
                (p, self.layout.effect_of(p))
            }
            Shape::Nested => {
                let (mut row, mut col, mut at) = (0, 0, 0);
                for (a, g) in self.axes.iter().zip(&self.grids) {
                    let (r, c) = g.cell_of(point(a, at));
                    at += a.arity();
                    row = row * g.rows + r;
                    col = col * g.cols + c;
                }
                (self.layout.center(row, col), row * self.layout.cols + col)
            }
        }
    }
}

/// An angle wrapped to `[-pi, pi)`.
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let w = (a + PI).rem_euclid(TAU) - PI;
    if w >= PI {
        -PI
    } else {
        w
    }
}
