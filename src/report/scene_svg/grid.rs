//! The picture of a grid scene.

use super::*;

/// The picture of a grid scene; with `animated`, what moves is drawn by
/// it after the path (the agent, see
/// [`grid_motion_svg`](super::motion_svg::grid_motion_svg)).
pub(in crate::report) fn grid_picture(
    scene: &Scene,
    g: &GridSpec,
    overlay: Option<&Overlay>,
    mut animated: Option<Layer>,
) -> String {
    let eg = g.effect_grid();
    let mut v = View::new(eg.min, eg.max);
    let mut keys = vec![Key(Swatch::Letter("#1f4e9c", 'S'), "start cell")];
    keys.extend(reward_keys(scene));
    keys.push(Key(Swatch::Line("#333", None), "wall"));
    if overlay.is_some() {
        path_keys(&mut keys, None);
    }
    if animated.is_some() {
        keys.push(Key(Swatch::Dot(TRACKED), "agent"));
    }
    v.legend_rows = legend_rows(&keys, v.width());
    let mut out = String::new();
    header(&mut out, &v, scene, overlay);
    effect_layer(&mut out, &v, scene, overlay);
    // the border and the walls
    let (w, h) = (eg.max[0] - eg.min[0], eg.max[1] - eg.min[1]);
    let at = v.rect((eg.min[0], eg.max[1]), w, h);
    let _ = writeln!(
        out,
        r##"<rect {at} fill="none" stroke="#333" stroke-width="4"/>"##
    );
    let rows = g.rows as f64;
    for &((r1, c1), (r2, c2)) in &g.walls {
        let (x0, y0, x1, y1) = if r1 == r2 {
            let x = c1.max(c2) as f64;
            (x, rows - r1 as f64, x, rows - r1 as f64 - 1.0)
        } else {
            let y = rows - r1.max(r2) as f64;
            (c1 as f64, y, c1 as f64 + 1.0, y)
        };
        let _ = writeln!(
            out,
            r##"<line {} stroke="#333" stroke-width="6" stroke-linecap="round"/>"##,
            v.segment((x0, y0), (x1, y1))
        );
    }
    let s = eg.center(g.start.0, g.start.1);
    let (x, y, size) = (v.x(s[0] - 0.3), v.y(s[1] + 0.28), v.len(0.25));
    let _ = writeln!(
        out,
        r##"<text x="{x:.2}" y="{y:.2}" font-size="{size:.0}" text-anchor="middle" dominant-baseline="central" fill="#1f4e9c" font-weight="bold">S</text>"##
    );
    path_layer(&mut out, &v, overlay);
    if let Some(draw) = animated.as_mut() {
        draw(&mut out, &v);
    }
    axes(&mut out, &v, "cells");
    legend(&mut out, &v, &keys);
    out.push_str("</svg>\n");
    out
}
