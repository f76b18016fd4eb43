//! `e3d scene render --animate`'s animated SVG: its frames, one animated
//! element per moving body, the time readout, the refusal on a grid.

use e3d::report::motion_svg::{html_page, motion_svg, thin, AnimateError, MAX_FRAMES};
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
    let WorldSpec::Physics(p) = &scene.world else {
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
