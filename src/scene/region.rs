//! Named rectangular reward regions.

use super::Invalid;
use crate::effect::EffectGrid;
use serde::{Deserialize, Serialize};

/// A named rectangle of the plane, in metres: every effect cell whose
/// centre lies inside it (borders included) is rewarded, like the cells
/// listed in `reward.cells`.
///
/// ```ron
/// reward: (regions: [(name: "corner", min: (5.0, 0.0), max: (6.0, 1.0))]),
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// A name, for people and pictures.
    pub name: String,
    /// Lower-left corner `(x, y)`, metres.
    pub min: (f64, f64),
    /// Upper-right corner `(x, y)`, metres.
    pub max: (f64, f64),
}

impl RegionSpec {
    /// The cells `(row, col)` of `grid` whose centre lies in the region.
    pub fn cells(&self, grid: &EffectGrid) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for r in 0..grid.rows {
            for c in 0..grid.cols {
                let [x, y] = grid.center(r, c);
                if x >= self.min.0 && x <= self.max.0 && y >= self.min.1 && y <= self.max.1 {
                    out.push((r, c));
                }
            }
        }
        out
    }

    pub(crate) fn validate(&self, grid: &EffectGrid) -> Result<(), Invalid> {
        let at = format!("\"{}\"", self.name);
        crate::text::check_name(&self.name)
            .map_err(|e| Invalid::at("name", Some(&at), &format!("region: {e}")))?;
        let bad = |what: String| Err(Invalid::at("regions", Some(&at), &what));
        let finite = [self.min.0, self.min.1, self.max.0, self.max.1]
            .iter()
            .all(|v| v.is_finite());
        if !finite || self.min.0 >= self.max.0 || self.min.1 >= self.max.1 {
            return bad(format!(
                "region `{}`: finite corners with min < max, found min {:?}, max {:?}",
                self.name, self.min, self.max
            ));
        }
        if self.cells(grid).is_empty() {
            return bad(format!(
                "region `{}`: a rectangle holding the centre of at least one effect cell",
                self.name
            ));
        }
        Ok(())
    }
}
