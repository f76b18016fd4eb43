//! `e3d scene render`: what the pictures show and that their legend says
//! it, as drawn: the tracked point above the path's start, the reward
//! cell's fill unchanged under the terminal cell, the mirror line, the axes.

use crate::common::{e3d_command, temp_path};

fn render(scene: &str, command: Option<&str>) -> String {
    let dir = temp_path("pictures");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join(format!("{scene}-{}.svg", command.unwrap_or("none")));
    let mut args = vec!["scene".to_string(), "render".into(), scene.into()];
    if let Some(c) = command {
        args.push(format!("--command={c}"));
    }
    let o = e3d_command()
        .args(&args)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let svg = std::fs::read_to_string(&out).unwrap();
    let _ = std::fs::remove_file(&out);
    svg
}

/// The labels of the legend's entries, in order.
fn legend(svg: &str) -> Vec<String> {
    let start = svg.find(r#"<g class="legend""#).expect("a legend");
    let end = start + svg[start..].find("\n</g>").unwrap();
    svg[start..end]
        .lines()
        .filter(|l| l.starts_with(r#"<g class="key">"#))
        .map(|l| {
            let t = l.rsplit("\">").next().unwrap();
            t.trim_end_matches("</text></g>").to_string()
        })
        .collect()
}

/// The value of attribute `name` in the first element of `svg` that
/// contains `marker`.
fn attr(svg: &str, marker: &str, name: &str) -> String {
    let line = svg
        .lines()
        .find(|l| l.contains(marker))
        .unwrap_or_else(|| panic!("no element with `{marker}`"));
    let key = format!(" {name}=\"");
    let rest = &line[line
        .find(&key)
        .unwrap_or_else(|| panic!("no {name} in {line}"))
        + key.len()..];
    rest[..rest.find('"').unwrap()].to_string()
}

#[test]
fn arm7_shows_the_tracked_point_the_mirror_line_and_its_legend() {
    let svg = render("arm7", Some("-++++--"));
    let keys = legend(&svg);
    for k in [
        "start pose",
        "end pose",
        "tracked point",
        "reward cell",
        "path",
        "start of the path",
        "end of the path",
        "terminal cell",
        "mirror line (FlipY)",
    ] {
        assert!(
            keys.iter().any(|x| x == k),
            "no `{k}` in the legend {keys:?}"
        );
    }
    // the tracked point is drawn after (over) the ring of the path's start,
    // at its centre, and smaller: it stays visible
    let ring = svg.find("<title>start of the path</title>").unwrap();
    let point = svg.find("<title>tracked point</title>").unwrap();
    assert!(
        point > ring,
        "the tracked point is under the start of the path"
    );
    let ring_line = "<title>start of the path</title>";
    let point_line = "<title>tracked point</title>";
    assert_eq!(attr(&svg, ring_line, "fill"), "none");
    assert_eq!(attr(&svg, ring_line, "cx"), attr(&svg, point_line, "cx"));
    assert_eq!(attr(&svg, ring_line, "cy"), attr(&svg, point_line, "cy"));
    let r: f64 = attr(&svg, ring_line, "r").parse().unwrap();
    let rp: f64 = attr(&svg, point_line, "r").parse().unwrap();
    assert!(rp < r - 2.0, "{rp} vs {r}");
    // the mirror line is drawn as its legend swatch shows it
    let dash = attr(&svg, "<title>mirror line (FlipY)", "stroke-dasharray");
    let key = svg
        .lines()
        .find(|l| l.contains(">mirror line (FlipY)</text>"))
        .unwrap();
    assert!(
        key.contains(&format!(r#"stroke-dasharray="{dash}""#)),
        "{key}"
    );
}

/// On puck_rooms the command SEEEEES ends in the reward cell: the terminal
/// cell is an outline, so the reward cell keeps the fill of its swatch.
#[test]
fn the_terminal_cell_does_not_change_the_reward_cells_colour() {
    let svg = render("puck_rooms", Some("SEEEEES"));
    assert!(
        svg.contains("effect 17"),
        "the command ends in the reward cell (2, 5)"
    );
    let terminal = svg
        .lines()
        .find(|l| l.starts_with("<rect") && l.contains(r#"stroke-dasharray="7,3""#))
        .expect("the terminal cell");
    assert!(terminal.contains(r#"fill="none""#), "{terminal}");
    let cell = svg
        .lines()
        .find(|l| l.starts_with("<rect") && l.contains("fill-opacity") && !l.contains("stroke"))
        .expect("the reward cell");
    let swatch = svg
        .lines()
        .find(|l| l.contains(">reward cell</text>"))
        .expect("the reward cell's key");
    for a in ["fill", "fill-opacity"] {
        let v = attr(cell, "<rect", a);
        assert!(
            swatch.contains(&format!(r#" {a}="{v}""#)),
            "{a}={v} not in {swatch}"
        );
    }
    assert!(legend(&svg).contains(&"fixed body".to_string()));
}

/// Axes with ticks in world units: metres on a physics scene, cells on a
/// grid.
#[test]
fn pictures_have_axes_with_ticks_in_world_units() {
    let tick_labels = |svg: &str| -> Vec<String> {
        let line = svg
            .lines()
            .find(|l| l.contains(r#"class="tick-labels""#))
            .unwrap();
        let g = &line[line.find(r#"class="tick-labels""#).unwrap()..];
        g.split("</text>")
            .filter_map(|t| t.rsplit('>').next())
            .filter(|t| !t.is_empty())
            .map(str::to_string)
            .collect()
    };
    let arm = render("arm7", None);
    let labels = tick_labels(&arm);
    for t in ["-1.5", "-0.5", "0.0", "0.5", "1.5"] {
        assert!(labels.iter().any(|l| l == t), "no tick {t} in {labels:?}");
    }
    assert!(!labels.iter().any(|l| l == "-0.0"), "{labels:?}");
    assert!(arm.contains(">x (m)</text>") && arm.contains(">y (m)</text>"));
    assert!(arm.contains(r#"class="ticks""#));
    let grid = render("two_rooms", Some("SEEEEES"));
    let labels = tick_labels(&grid);
    // x: 0..6, y: 0..3, whole cells
    for t in 0..=6 {
        assert!(labels.contains(&t.to_string()), "no tick {t} in {labels:?}");
    }
    assert_eq!(labels.len(), 7 + 4, "{labels:?}");
    assert!(grid.contains(">x (cells)</text>") && grid.contains(">y (cells)</text>"));
    let keys = legend(&grid);
    for k in ["start cell", "reward cell", "wall", "path", "terminal cell"] {
        assert!(
            keys.iter().any(|x| x == k),
            "no `{k}` in the legend {keys:?}"
        );
    }
    // no symmetry on a grid, no mirror line in its legend
    assert!(!keys.iter().any(|x| x.starts_with("mirror")));
}

/// maze3's reward is a region: the legend names the region and its cell.
#[test]
fn a_reward_region_is_in_the_legend() {
    let keys = legend(&render("maze3", None));
    assert!(keys.contains(&"reward region".to_string()), "{keys:?}");
    assert!(keys.contains(&"reward cell".to_string()), "{keys:?}");
    assert!(
        !keys.contains(&"path".to_string()),
        "no command, no path: {keys:?}"
    );
}

/// A slider is drawn as a rail between its limits with end stops, not as
/// a hinge's ring, inside the picture; a product of features is named
/// in a note wrapped to the picture's width, which pushes the drawing
/// down rather than under it.
#[test]
fn a_slider_is_a_rail_and_a_long_effect_note_is_wrapped() {
    let svg = render("cart_pole", None);
    let start = svg
        .find("<g><title>rail: slider, limits [-1.5, 1.5] m</title>")
        .expect("the rail");
    let rail = &svg[start..start + svg[start..].find("</g>").unwrap()];
    assert_eq!(
        rail.matches("<line ").count(),
        3,
        "a rail and two stops: {rail}"
    );
    assert!(
        !svg.contains("<title>rail</title></circle>"),
        "a hinge ring for the slider"
    );
    let number = |s: &str, key: &str| -> f64 {
        let at = s.find(key).unwrap() + key.len();
        s[at..at + s[at..].find('"').unwrap()].parse().unwrap()
    };
    let width = number(&svg, "width=\"");
    for key in ["x1=\"", "x2=\""] {
        let x = number(rail, key);
        assert!(
            (0.0..=width).contains(&x),
            "the rail leaves the picture: {x} of {width}"
        );
    }
    let notes: Vec<&str> = svg
        .lines()
        .filter(|l| l.contains(r##"font-size="12" fill="#555""##))
        .collect();
    assert_eq!(notes.len(), 2, "{notes:?}");
    assert!(
        notes[0].contains("effect: joint `pivot`") && notes[1].contains("first feature"),
        "{notes:?}"
    );
    for n in &notes {
        let text = &n[n.find('>').unwrap() + 1..n.rfind('<').unwrap()];
        assert!(
            30.0 + 6.5 * text.chars().count() as f64 <= width - 30.0,
            "{text}"
        );
    }
    // the axes start below the note's second line (y 74)
    let axes = &svg[svg.find("<g class=\"axes\"").unwrap()..];
    let top: f64 = axes
        .split("V")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(top >= 84.0, "the drawing starts at {top}");
}
