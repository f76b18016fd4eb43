//! `e3d scene table`, `stats` and `render` on scenes with start contexts:
//! per context, as `scene exec` runs each command from each context.

use crate::common::{e3d, stdout_of, temp_dir};
use e3d::world::Episodic;
use e3d::world::{ContextTables, TabledContexts};
use e3d::Scene;

// two_rooms from two named cells (contexts `a` and `b`)
use crate::contexts::CONTEXTS as GRID;

/// A puck in a 3 m room, 2 impulses (4 commands), started in two corners.
const PUCK: &str = r#"Scene(
    name: "puck_corners",
    world: Physics(
        walls: [(name: "wall", room: ((0.0, 0.0), (3.0, 3.0)), placement: Outside, thickness: 0.1)],
        bodies: [(name: "puck", shape: Ball(radius: 0.2), mass: 1.0, position: (0.5, 0.5),
                  linear_damping: 1.5, friction: 0.0, lock_rotation: true)],
        contexts: [(name: "low", bodies: [(body: "puck", position: (0.5, 0.5))]),
                   (name: "high", bodies: [(body: "puck", position: (2.5, 2.5))])],
        schedule: Sequential(phase: 1.0, settle: 1.0),
        effect: (body: "puck", grid: (rows: 3, cols: 3, min: (0.0, 0.0), max: (3.0, 3.0))),
    ),
    command: Repeat(slots: 2, alphabet: [(symbol: 'E', action: Impulse(body: "puck", impulse: (1.6, 0.0))),
                                         (symbol: 'N', action: Impulse(body: "puck", impulse: (0.0, 1.6)))]),
)"#;

/// The effects `scene exec` gives each (context, command), context by
/// context: `[context][command index]`.
fn exec_effects(scene: &str, commands: &[&str], contexts: usize) -> Vec<Vec<usize>> {
    let mut args = vec!["scene", "exec", scene];
    args.extend(commands);
    let out = stdout_of(&args);
    let header: Vec<&str> = out.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "effect").unwrap();
    let mut per = vec![Vec::new(); contexts];
    for (i, line) in out.lines().skip(1).enumerate() {
        per[i % contexts].push(line.split(',').nth(col).unwrap().parse().unwrap());
    }
    per
}

#[test]
fn scene_table_keys_the_outcomes_by_context_and_command() {
    let dir = temp_dir("context-table");
    std::fs::create_dir_all(&*dir).unwrap();
    let path = dir.join("ctx.ron");
    std::fs::write(&path, GRID).unwrap();
    let file = path.to_str().unwrap();
    let cache = dir.join("tables");
    let args = ["scene", "table", file, "--cache", cache.to_str().unwrap()];
    let first = stdout_of(&args);
    assert!(
        first.contains("2 start contexts x 16384 commands = 32768 outcomes"),
        "{first}"
    );
    assert_eq!(first.matches("written to").count(), 2, "{first}");
    let second = stdout_of(&args);
    assert_eq!(second.matches("read from").count(), 2, "{second}");
    // one file per context, beside no plain table
    let mut names: Vec<String> = std::fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names.len(), 2, "{names:?}");
    assert!(
        names[0].starts_with("two_rooms_contexts.a-")
            && names[1].starts_with("two_rooms_contexts.b-")
    );
    // the files hold what exec gives from each context, command by command
    let scene = Scene::load(&path).unwrap();
    let (tables, read) = ContextTables::cached(
        TabledContexts::of(&scene).unwrap(),
        &cache,
        &e3d::Control::default(),
    )
    .unwrap();
    assert!(read);
    let space = scene.command_space();
    let commands = ["EEEEESS", "SSSSWWW", "NNNNNNN", "WSWSWSE"];
    let exec = exec_effects(file, &commands, 2);
    for (k, effects) in exec.iter().enumerate() {
        for (c, &e) in commands.iter().zip(effects) {
            let o = tables.table(k).lookup(&space.parse(c).unwrap()).unwrap();
            assert_eq!(o.effect, e, "context {k} command {c}");
        }
    }
    // the two contexts' tables differ (EEEEESS: cell 14 from a, 17 from b)
    assert_eq!(exec[0][0], 14);
    assert_eq!(exec[1][0], 17);
    // every outcome is the world's from the context's start
    let mut world = scene.build();
    for k in 0..2 {
        let from = e3d::world::seed0_start(&world, k).unwrap();
        for i in (0..16384).step_by(97) {
            let c = space.command_at(i);
            assert_eq!(
                tables.table(k).get(i),
                &world.execute_outcome_from(&from, &c).unwrap()
            );
        }
    }
    // a drawn context cannot be tabled: refused, named
    let drawn = GRID.replace(
        "(name: \"b\", cell: (2, 5))",
        "(name: \"anywhere_b\", cell: (0, 3), to: (2, 5))",
    );
    std::fs::write(&path, drawn).unwrap();
    let out = e3d(&["scene", "table", file]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("context `anywhere_b` is drawn from a range")
            && err.contains("cannot be tabled"),
        "{err}"
    );
}

#[test]
fn scene_stats_counts_each_context_and_their_union() {
    let dir = temp_dir("context-stats");
    std::fs::create_dir_all(&*dir).unwrap();
    let path = dir.join("puck.ron");
    std::fs::write(&path, PUCK).unwrap();
    let file = path.to_str().unwrap();
    let out = stdout_of(&["scene", "stats", file]);
    let exec = exec_effects(file, &["EE", "EN", "NE", "NN"], 2);
    let mut union = std::collections::BTreeSet::new();
    for (name, effects) in ["low", "high"].iter().zip(&exec) {
        let reached: std::collections::BTreeSet<usize> = effects.iter().copied().collect();
        union.extend(reached.iter().copied());
        let line = out
            .lines()
            .find(|l| l.starts_with(&format!("context {name}:")))
            .unwrap_or_else(|| panic!("{out}"));
        assert!(
            line.contains(&format!("reached cells {} of 9", reached.len())),
            "{line} vs {effects:?}"
        );
        // the counts per cell: every command of the context, in its cell
        let counts = out.lines().skip_while(|l| *l != line).nth(1).unwrap();
        let mut want: Vec<String> = Vec::new();
        for cell in &reached {
            let n = effects.iter().filter(|e| *e == cell).count();
            want.push(format!("{cell}:{n}"));
        }
        assert_eq!(
            counts.trim(),
            format!("commands per cell: {}", want.join(" "))
        );
    }
    // the two corners reach different cells; the union counts both
    assert_ne!(exec[0], exec[1]);
    assert!(
        out.contains(&format!(
            "all contexts: reached cells {} of 9 (the union)",
            union.len()
        )),
        "{out}"
    );
}

#[test]
fn scene_render_draws_each_context_from_its_start() {
    let dir = temp_dir("context-render");
    std::fs::create_dir_all(&*dir).unwrap();
    let path = dir.join("puck.ron");
    std::fs::write(&path, PUCK).unwrap();
    let file = path.to_str().unwrap();
    let svg_path = dir.join("all.svg");
    stdout_of(&["scene", "render", file, "--out", svg_path.to_str().unwrap()]);
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    assert!(
        svg.contains("puck_corners: context low") && svg.contains("puck_corners: context high")
    );
    assert_eq!(
        svg.matches("<svg ").count(),
        3,
        "an outer picture and two panels"
    );
    // the puck drawn in two places: one per context's start
    let circles: Vec<&str> = svg
        .split("<title>puck</title>")
        .skip(1)
        .map(|s| s.split("cx=\"").nth(1).unwrap().split('"').next().unwrap())
        .collect();
    assert_eq!(circles.len(), 2);
    assert_ne!(circles[0], circles[1]);
    // one context, a command from it: the effect exec gives from it
    let one = dir.join("high.svg");
    stdout_of(&[
        "scene",
        "render",
        file,
        "--context",
        "high",
        "--command",
        "EN",
        "--out",
        one.to_str().unwrap(),
    ]);
    let svg = std::fs::read_to_string(&one).unwrap();
    let effect = exec_effects(file, &["EN"], 2)[1][0];
    assert!(
        svg.contains(&format!("command EN  →  effect {effect} ")),
        "{effect}"
    );
    assert!(svg.contains("puck_corners: context high") && !svg.contains("context low"));
    // an unknown context is refused with the names
    let out = e3d(&[
        "scene",
        "render",
        file,
        "--context",
        "mid",
        "--out",
        one.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("no start context `mid` (its contexts: low, high)"));
}

/// `e3d scene render --animate --context NAME` animates the rollout from
/// that context's start: its readout ends on the effect `scene exec` gives
/// from there (a physics scene and a grid), the contexts' apart, and the
/// faint start pose drawn under a physics animation is the context's; an
/// unknown context, or one on a scene without contexts, is refused.
#[test]
fn scene_render_animates_from_a_context() {
    let dir = temp_dir("context-animate");
    let path = dir.join("puck.ron");
    std::fs::write(&path, PUCK).unwrap();
    let grid = dir.join("grid.ron");
    std::fs::write(&grid, GRID).unwrap();
    for (file, command) in [(&path, "EN"), (&grid, "WWWWWWW")] {
        let file = file.to_str().unwrap();
        let names: Vec<String> = e3d::world::start_contexts(&Scene::load(file).unwrap())
            .into_iter()
            .map(|c| c.name)
            .collect();
        assert_eq!(names.len(), 2);
        let effects = exec_effects(file, &[command], 2);
        let mut pictures = Vec::new();
        for (k, name) in names.iter().enumerate() {
            let out = dir.join(format!("{name}.svg"));
            let args = ["scene", "render", file, "--command", command, "--animate"];
            let to = ["--context", name, "--out", out.to_str().unwrap()];
            stdout_of(&[&args[..], &to[..]].concat());
            let svg = std::fs::read_to_string(&out).unwrap();
            let effect = effects[k][0];
            assert!(
                svg.contains(&format!("effect {effect}")),
                "{file} {name}: {effect}"
            );
            pictures.push(svg);
        }
        assert_ne!(
            effects[0][0], effects[1][0],
            "{file}: the contexts end apart"
        );
        if file.ends_with("puck.ron") {
            // the faint puck at each context's start: two places
            let faint = |svg: &str| {
                let s = svg.split("<g><title>puck</title>").nth(1).unwrap();
                s.split("cx=\"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap()
                    .to_string()
            };
            assert_ne!(faint(&pictures[0]), faint(&pictures[1]));
        }
        let x = dir.join("x.svg");
        let out = e3d(&[
            "scene",
            "render",
            file,
            "--command",
            command,
            "--animate",
            "--context",
            "mid",
            "--out",
            x.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&out.stderr).contains("no start context `mid`"));
    }
    let y = dir.join("y.svg");
    let out = e3d(&[
        "scene",
        "render",
        "puck_rooms",
        "--command",
        "EEEEEEE",
        "--animate",
        "--context",
        "a",
        "--out",
        y.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("has no start contexts"));
}

/// `e3d run --table-cache DIR` on a scene with named start contexts looks
/// its commands up in the contexts' tables that `scene table --cache DIR`
/// wrote (said on stderr), with the same results as simulating them; with
/// no table there it says so and simulates.
#[test]
fn run_reads_the_context_tables_of_its_cache() {
    let dir = temp_dir("context-run-tables");
    let path = dir.join("puck.ron");
    std::fs::write(&path, PUCK).unwrap();
    let file = path.to_str().unwrap();
    let cache = dir.join("tables");
    let cache_s = cache.to_str().unwrap();
    let run = ["run", file, "--trials", "60", "--sessions", "2"];
    let plain = stdout_of(&run);
    let with_cache = [&run[..], &["--table-cache", cache_s]].concat();
    let before = e3d(&with_cache);
    assert!(before.status.success());
    let err = String::from_utf8_lossy(&before.stderr);
    assert!(
        err.contains("note: no outcome table of a start context in"),
        "{err}"
    );
    assert_eq!(String::from_utf8_lossy(&before.stdout), plain);
    stdout_of(&["scene", "table", file, "--cache", cache_s]);
    let after = e3d(&with_cache);
    assert!(after.status.success());
    let err = String::from_utf8_lossy(&after.stderr);
    assert!(
        err.contains("outcomes: the tables of start contexts low, high read from"),
        "{err}"
    );
    assert_eq!(String::from_utf8_lossy(&after.stdout), plain);
}
