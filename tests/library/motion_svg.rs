//! `e3d scene render --animate`'s animated SVG: its frames, one animated
//! element per moving body, the time readout, the refusal on a grid; the
//! grid's animated cell path.

use e3d::report::motion_svg::{
    grid_motion_svg, html_page, motion_svg, thin, AnimateError, MAX_FRAMES,
};
use e3d::scene::physics::BodyKind;
use e3d::scene::WorldSpec;
use e3d::Scene;

fn animated(name: &str, command: &str) -> (Scene, e3d::world::Motion, String) {
    let scene = Scene::builtin(name).unwrap();
    let mut w = scene.physics_world().unwrap();
    let c = scene.command_space().parse(command).unwrap();
    let m = w.motion(&c).unwrap();
    let svg = motion_svg(&scene, command, &m).unwrap();
    (scene, m, svg)
}

#[test]
fn arm7_has_a_body_per_moving_body_frames_and_a_time_readout() {
    let (scene, m, svg) = animated("arm7", "+0-+0-+");
    let WorldSpec::Physics(p) = &scene.spec().world else {
        panic!("arm7 is physics")
    };
    let moving: Vec<_> = p
        .bodies
        .iter()
        .filter(|b| b.kind != BodyKind::Fixed)
        .collect();
    assert_eq!(svg.matches(r#"class="body""#).count(), moving.len());
    for b in &moving {
        assert!(
            svg.contains(&format!(r#"data-body="{}""#, b.name)),
            "{}",
            b.name
        );
    }
    // two transforms per moving body (translate, rotate)
    assert_eq!(svg.matches("<animateTransform").count(), 2 * moving.len());
    let kept = thin(m.frames.len(), MAX_FRAMES).len();
    assert!(kept <= MAX_FRAMES);
    assert_eq!(svg.matches(r#"class="frame""#).count(), kept);
    assert!(svg.contains("t = 0.000 s"));
    let end = m.frames.last().unwrap().time;
    assert!(svg.contains(&format!("t = {end:.3} s / {end:.3} s")));
    // every animation has as many values as key times
    let first = svg.split("<animateTransform").nth(1).unwrap();
    let attr = |name: &str| {
        let s = first.split(&format!(r#"{name}=""#)).nth(1).unwrap();
        s[..s.find('"').unwrap()].split(';').count()
    };
    assert_eq!(attr("values"), kept);
    assert_eq!(attr("keyTimes"), kept);
    assert!(svg.contains(r#"class="tracked""#));
    assert!(svg.len() < 1_000_000, "{} bytes", svg.len());
    assert!(!svg.contains("<script"));
}

#[test]
fn the_page_holds_the_svg_and_no_script() {
    let (_, _, svg) = animated("arm7", "+++++++");
    let page = html_page("arm7", &svg);
    assert!(page.starts_with("<!DOCTYPE html>"));
    assert!(page.contains(&svg));
    assert!(!page.contains("<script"));
}

#[test]
fn thinning_keeps_first_and_last() {
    let idx = thin(1001, 150);
    assert!(idx.len() <= 150);
    assert_eq!(idx[0], 0);
    assert_eq!(*idx.last().unwrap(), 1000);
    assert!(thin(0, 150).is_empty());
}

#[test]
fn a_grid_is_refused_with_a_reason() {
    let (_, m, _) = animated("arm7", "+0-+0-+");
    let grid = Scene::builtin("two_rooms").unwrap();
    let e = motion_svg(&grid, "E", &m).unwrap_err();
    assert!(matches!(e, AnimateError::Grid(_)));
    assert!(e.to_string().contains("grid"));
}

/// The values of the first `<animate attributeName="ATTR"` of `svg`.
fn animated_values<'a>(svg: &'a str, attr: &str) -> Vec<&'a str> {
    let a = svg
        .split(&format!(r#"<animate attributeName="{attr}""#))
        .nth(1)
        .unwrap();
    let v = a.split(r#"values=""#).nth(1).unwrap();
    v[..v.find('"').unwrap()].split(';').collect()
}

#[test]
fn a_grid_animates_the_cell_path_a_keyframe_per_slot() {
    let scene = Scene::builtin("two_rooms").unwrap();
    let space = scene.command_space();
    let c = space.parse("EEESSEE").unwrap();
    let svg = grid_motion_svg(&scene, &c).unwrap();
    let slots = space.num_slots();
    // the cells: start (0, 0), E E to (0, 2), E into the wall, S S, E E into the wall
    let cells = [
        (0, 0),
        (0, 1),
        (0, 2),
        (0, 2),
        (1, 2),
        (2, 2),
        (2, 2),
        (2, 2),
    ];
    assert_eq!(cells.len(), slots + 1);
    let xs = animated_values(&svg, "cx");
    let ys = animated_values(&svg, "cy");
    assert_eq!((xs.len(), ys.len()), (slots + 1, slots + 1));
    let key_times: Vec<&str> = {
        let a = svg.split(r#"<circle class="agent""#).nth(1).unwrap();
        let k = a.split(r#"keyTimes=""#).nth(1).unwrap();
        k[..k.find('"').unwrap()].split(';').collect()
    };
    assert_eq!(key_times.len(), slots + 1);
    assert_eq!(key_times[0], "0.0000");
    // one readout per keyframe, naming the slot's symbol and the cell
    assert_eq!(svg.matches(r#"class="keyframe""#).count(), slots + 1);
    assert!(svg.contains("start: cell (0, 0)"));
    for (k, (r, col)) in cells.iter().enumerate().skip(1) {
        let sym = "EEESSEE".chars().nth(k - 1).unwrap();
        assert!(
            svg.contains(&format!("slot {k}/{slots}: {sym} → cell ({r}, {col})")),
            "slot {k}"
        );
    }
    // the agent moves as the cells do: same x where the column is the same
    for k in 1..cells.len() {
        assert_eq!(xs[k] == xs[k - 1], cells[k].1 == cells[k - 1].1, "x {k}");
        assert_eq!(ys[k] == ys[k - 1], cells[k].0 == cells[k - 1].0, "y {k}");
    }
    // the still picture is there: the walls and the whole path
    let walls = match &scene.spec().world {
        WorldSpec::Grid(g) => g.walls.len(),
        _ => unreachable!(),
    };
    assert_eq!(
        svg.matches(r#"stroke-width="6" stroke-linecap="round""#)
            .count(),
        walls
    );
    assert!(svg.contains("<polyline") && svg.contains("end of the path"));
    assert!(svg.contains("command EEESSEE"));
    assert!(!svg.contains("<script"));
}

#[test]
fn a_grid_animation_refuses_physics_and_bad_commands() {
    let arm = Scene::builtin("arm7").unwrap();
    let c = arm.command_space().parse("+0-+0-+").unwrap();
    assert!(matches!(
        grid_motion_svg(&arm, &c).unwrap_err(),
        AnimateError::NotGrid(_)
    ));
    let grid = Scene::builtin("two_rooms").unwrap();
    let short = e3d::Command::new(vec![0, 1]);
    let e = grid_motion_svg(&grid, &short).unwrap_err();
    assert!(matches!(e, AnimateError::Command(_)), "{e}");
}
