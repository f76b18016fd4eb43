//! `e3d scene check`: the sampled reachability estimate and the geometric
//! warnings, asserted on their messages.

use crate::common::{e3d_command, stdout_of, temp_dir, temp_path};

fn check(args: &[&str]) -> (String, String) {
    let out = e3d_command()
        .args(["scene", "check"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// three_rooms as it was written body by body (scenes/three_rooms.ron now
/// writes its walls as a shorthand), for edits of single walls.
fn three_rooms_bodies() -> String {
    std::fs::read_to_string("tests/scenes/three_rooms_expanded.ron").unwrap()
}

fn builtin(name: &str) -> String {
    e3d::scene::BUILTIN
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap()
        .1
        .to_string()
}

fn write(name: &str, text: &str) -> String {
    let dir = temp_path("check");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

#[test]
fn a_sane_scene_gets_no_warning_and_exact_counts_when_small() {
    // 81 commands <= 200 samples: executed whole
    let (out, err) = check(&["arm4_gravity"]);
    assert!(out.contains("reach: all 81 commands executed ("), "{out}");
    assert!(out.contains("): 30 of 100 cells reached"), "{out}");
    assert!(
        out.contains("reward cells reached by 1 of 81 commands (1.235%)"),
        "{out}"
    );
    // no warning; on a slow machine the estimated cost and the progress
    // come first (their times are the machine's, so not asserted on)
    let warnings: Vec<&str> = err
        .lines()
        .filter(|l| !l.starts_with("scene check arm4_gravity: "))
        .collect();
    assert!(warnings.is_empty(), "a sane scene gets no warning: {err}");
}

#[test]
fn a_sampled_scene_reports_the_reward_probability() {
    // two_rooms rewarding its start cell: a common cell
    let text = builtin("two_rooms").replace("reward: (cells: [(2, 5)]", "reward: (cells: [(0, 0)]");
    assert_ne!(text, builtin("two_rooms"));
    let f = write("common.ron", &text);
    let (out, err) = check(&[&f, "--samples", "300", "--seed", "3"]);
    assert!(
        out.contains("reach (estimate): 300 random commands of 16384 (seed 3, "),
        "{out}"
    );
    let line = out
        .lines()
        .find(|l| l.starts_with("reward cells: estimated probability"))
        .unwrap();
    let hits: u64 = line
        .split('(')
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        hits > 0 && line.ends_with(&format!("({hits} of 300 sampled commands)")),
        "{line}"
    );
    assert_eq!(err, "");
    // the same seed gives the same sample
    let (again, _) = check(&[&f, "--samples", "300", "--seed", "3"]);
    let strip = |s: &str| {
        s.lines()
            .filter(|l| !l.starts_with("reach"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(strip(&out), strip(&again));
}

#[test]
fn an_unreachable_reward_cell_is_warned_about() {
    // arm4_gravity's tip never reaches the top-left corner: all 81 commands say so
    let text = builtin("arm4_gravity").replace("cells: [(3, 2)]", "cells: [(0, 0)]");
    let f = write("corner.ron", &text);
    let (out, err) = check(&[&f]);
    assert!(
        out.contains("reward cells reached by 0 of 81 commands (0.000%)"),
        "{out}"
    );
    assert!(
        err.contains("warning: scene arm4_gravity: no command reaches a reward cell [(0, 0)] (every command executed)"),
        "{err}"
    );
    // sampled: three_rooms' reward moved behind a closed wall (a room with no door)
    let text = three_rooms_bodies()
        .replace("position: (6.0, 2.5)", "position: (6.0, 2.0)")
        .replace(
            "height: 1.0),\n             position: (6.0, 2.0)",
            "height: 2.0),\n             position: (6.0, 2.0)",
        )
        .replace("cells: [(2, 8)]", "cells: [(0, 8)]");
    assert!(text.contains("Cuboid(width: 0.1, height: 2.0),\n             position: (6.0, 2.0)"));
    let f = write("closed.ron", &text);
    let (out, err) = check(&[&f, "--samples", "64"]);
    assert!(
        out.contains("reach (estimate): 64 random commands of 262144 (seed 0, "),
        "{out}"
    );
    assert!(
        out.contains("reward cells: estimated probability 0.000% (0 of 64 sampled commands)"),
        "{out}"
    );
    assert!(
        err.contains("warning: scene three_rooms: no sampled command reached a reward cell [(0, 8)]: it may be unreachable, or rarer than about 4.69% (95% bound); a full check (`e3d scene reward-cell three_rooms`) simulates 262144 commands: about "),
        "{err}"
    );
    assert!(err.contains(" by the cost model"), "{err}");
}

#[test]
fn a_wall_outside_the_grid_and_a_start_outside_it_are_warned_about() {
    let text = three_rooms_bodies()
        .replace("position: (4.5, -0.05)", "position: (4.5, -5.05)")
        .replace(
            "position: (0.5, 2.5),\n                linear_damping",
            "position: (10.5, 2.5),\n                linear_damping",
        )
        .replace("position: (9.05, 1.5)", "position: (11.05, 1.5)");
    let f = write("misplaced.ron", &text);
    let (_, err) = check(&[&f, "--samples", "0"]);
    assert!(err.contains("warning: scene three_rooms: fixed body `wall_south` spans [-0.1, 9.1] x [-5.1, -5], wholly outside the effect grid [0, 9] x [0, 3]: it bounds no motion on the grid (a misplaced wall?)"), "{err}");
    assert!(err.contains("warning: scene three_rooms: the tracked point starts at (10.5, 2.5), outside the effect grid [0, 9] x [0, 3]"), "{err}");
    assert!(err.contains("warning: scene three_rooms: dynamic body `puck` starts at (10.5, 2.5), outside the effect grid"), "{err}");
    // the puck, moved past the old east wall, is no longer in a room
    assert!(err.contains("warning: scene three_rooms: the walls do not enclose the tracked body `puck`: from its start (10.5, 2.5) it may leave them near"), "{err}");
    assert_eq!(err.lines().count(), 5, "{err}");
}

#[test]
fn a_wall_through_the_puck_is_refused() {
    let text = three_rooms_bodies().replace("position: (3.0, 2.5)", "position: (0.5, 2.5)");
    let f = write("through.ron", &text);
    let out = e3d_command().args(["scene", "check", &f]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("body `puck`: a start pose where it does not overlap `ab_high`"),
        "{err}"
    );
}

#[test]
fn sample_reach_is_exact_on_a_small_space_and_repeats_by_seed() {
    use e3d::world::sample_reach;
    use e3d::{OutcomeTable, Scene};
    let arm = Scene::builtin("arm4_gravity").unwrap();
    let s = sample_reach(&arm, 200, 0).unwrap();
    assert!(s.exhaustive);
    assert_eq!(s.samples, 81);
    let table = OutcomeTable::build(&mut arm.build()).unwrap();
    assert_eq!(s.counts, table.effect_counts());
    assert_eq!(s.reached_cells(), 30);
    assert_eq!(s.hits(&[3 * 10 + 2]), 1);
    let grid = Scene::builtin("two_rooms").unwrap();
    let a = sample_reach(&grid, 500, 9).unwrap();
    let b = sample_reach(&grid, 500, 9).unwrap();
    assert!(!a.exhaustive);
    assert_eq!((a.samples, a.counts.iter().sum::<u64>()), (500, 500));
    assert_eq!(a.counts, b.counts);
    assert_ne!(a.counts, sample_reach(&grid, 500, 10).unwrap().counts);
}

/// The closed-room warning: puck_rooms' walls enclose the puck; a gap in
/// them is named by a point near it.
#[test]
fn walls_with_a_gap_are_warned_about_with_a_point_near_it() {
    let (_, err) = check(&["--samples", "0", "puck_rooms"]);
    assert!(!err.contains("do not enclose"), "{err}");
    // the east wall cut by a door y in [0.2, 0.8] (wider than the puck's 0.4 m)
    let text = builtin("puck_rooms").replace(
        "placement: Outside,",
        "placement: Outside, doors: [((6.0, 0.2), (6.0, 0.8))],",
    );
    let (_, err) = check(&["--samples", "0", &write("east_gap.ron", &text)]);
    let line = err
        .lines()
        .find(|l| l.contains("do not enclose"))
        .unwrap_or_else(|| panic!("no warning: {err}"));
    assert!(
        line.contains("the walls do not enclose the tracked body `puck`: from its start (0.5, 2.5) it may leave them near (6."),
        "{line}"
    );
    // the point: at the gap, x just past the wall's line, y within the gap
    let near = line.split("near (").nth(1).unwrap();
    let (x, rest) = near.split_once(", ").unwrap();
    let y: f64 = rest.split(')').next().unwrap().parse().unwrap();
    let x: f64 = x.parse().unwrap();
    assert!(
        (6.0..=6.2).contains(&x) && (0.2..=0.8).contains(&y),
        "{line}"
    );
    // a gap narrower than the puck's radius is no way out
    let text = builtin("puck_rooms").replace(
        "placement: Outside,",
        "placement: Outside, doors: [((6.0, 0.4), (6.0, 0.55))],",
    );
    let (_, err) = check(&["--samples", "0", &write("narrow_gap.ron", &text)]);
    assert!(!err.contains("do not enclose"), "{err}");
    // no wall at all on the north side: the puck leaves through the top
    let text = std::fs::read_to_string("tests/scenes/puck_rooms_expanded.ron")
        .unwrap()
        .replace("position: (3.0, 3.05)", "position: (3.0, 13.05)");
    let (_, err) = check(&["--samples", "0", &write("no_north.ron", &text)]);
    assert!(
        err.contains("from its start (0.5, 2.5) it may leave them near (0.52, 3.07)"),
        "{err}"
    );
}

/// Accuracy is a choice `scene check` shows: the solver's iterations per
/// step on every physics scene, and with `--accuracy N` a row per
/// setting (1, 2, 3, 4, 8 and the scene's own, marked) with the share of
/// N commands in the converged run's cell and what a command costs.
#[test]
fn check_shows_the_solver_setting_and_measures_accuracy() {
    let out = stdout_of(&[
        "scene",
        "check",
        "arm7",
        "--samples",
        "0",
        "--accuracy",
        "40",
    ]);
    assert!(
        out.contains("solver: 4 iteration(s) per step, Rapier's default (`--accuracy`"),
        "{out}"
    );
    let rows: Vec<&str> = out
        .lines()
        .filter(|l| l.trim_start().starts_with("solver_iterations: "))
        .collect();
    assert_eq!(rows.len(), 5, "{out}");
    let share = |row: &str| -> f64 {
        let pct = row.split('%').next().unwrap();
        pct.split_whitespace().last().unwrap().parse().unwrap()
    };
    let shares: Vec<f64> = rows.iter().map(|r| share(r)).collect();
    assert!(shares.iter().all(|s| (0.0..=100.0).contains(s)), "{out}");
    // the finest setting lands at least as often as the coarsest
    assert!(shares[4] >= shares[0], "{out}");
    assert!(rows[3].starts_with("  solver_iterations: 4 ") && rows[3].ends_with("<- the scene's"));
    // a scene's own setting is listed and marked
    let d = temp_dir("accuracy-own");
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/arm7.ron"))
        .unwrap()
        .replacen("dt:", "solver_iterations: 6,\n    dt:", 1);
    let f = d.join("arm7_6.ron");
    std::fs::write(&f, text).unwrap();
    let out = stdout_of(&[
        "scene",
        "check",
        f.to_str().unwrap(),
        "--samples",
        "0",
        "--accuracy",
        "5",
    ]);
    assert!(out.contains("solver: 6 iteration(s) per step ("), "{out}");
    let own: Vec<&str> = out
        .lines()
        .filter(|l| l.ends_with("<- the scene's"))
        .collect();
    assert_eq!(own.len(), 1, "{out}");
    assert!(own[0].starts_with("  solver_iterations: 6 "), "{out}");
    // a grid has no solver
    let grid = stdout_of(&[
        "scene",
        "check",
        "two_rooms",
        "--samples",
        "0",
        "--accuracy",
        "5",
    ]);
    assert!(
        grid.contains("accuracy: a grid scene has no solver iterations"),
        "{grid}"
    );
    assert!(!grid.contains("solver: "), "{grid}");
}

/// `scene check` says what each slot's symbols do (runs of equal slots on
/// one line) and where each start context puts its bodies and joints,
/// after the lines it always printed.
#[test]
fn check_lists_each_slots_actions_and_each_contexts_start() {
    let (arm, _) = check(&["arm7", "--samples", "0"]);
    let lines: Vec<&str> = arm.lines().collect();
    let at = lines.iter().position(|l| *l == "actions:").unwrap();
    assert!(lines[at - 1].starts_with("reward cells: [(6, 5)]"), "{arm}");
    assert_eq!(
        lines[at + 1],
        "  0: -: torque -1.8 N·m on hinge `j1` (ground -> link1), held; 0: nothing; +: torque 1.8 N·m on hinge `j1` (ground -> link1), held"
    );
    assert_eq!(lines.len(), at + 8, "{arm}");

    let (puck, _) = check(&["scenes/puck_contexts.ron", "--samples", "0"]);
    assert!(
        puck.contains("start contexts (2): room_a (named: puck), room_b (named: puck)\n"),
        "{puck}"
    );
    assert!(puck.contains("actions:\n  0-6: E: impulse (1.6, 0) N·s on `puck`, once; S: impulse (0, -1.6) N·s on `puck`, once;"), "{puck}");
    assert!(
        puck.ends_with(
            "start context room_a: `puck` at (0.5, 2.5)\nstart context room_b: `puck` at (5.5, 0.5)\n"
        ),
        "{puck}"
    );
    let (poses, _) = check(&["scenes/arm7_poses.ron", "--samples", "0"]);
    assert!(
        poses.ends_with("start context curled: joint `j2` at 1.5 rad; joint `j4` at 1.5 rad\n"),
        "{poses}"
    );

    let (grid, _) = check(&["two_rooms", "--samples", "0"]);
    assert!(grid.ends_with("actions:\n  0-6: E: move east (drow 0, dcol 1); S: move south (drow 1, dcol 0); W: move west (drow 0, dcol -1); N: move north (drow -1, dcol 0)\n"), "{grid}");

    let slider = write(
        "check-slider.ron",
        r#"Scene(
    name: "slider",
    world: Physics(
        bodies: [(name: "cart", shape: Cuboid(width: 0.4, height: 0.2), mass: 1.0)],
        joints: [(name: "rail", parent: "ground", child: "cart",
                  kind: Prismatic(axis: (1.0, 0.0)), limits: (-1.0, 1.0), damping: 0.5,
                  motor: (stiffness: 4.0, damping: 1.0))],
        schedule: Simultaneous(push: 0.5, settle: 0.5),
        effect: (body: "cart", grid: (rows: 1, cols: 4, min: (-1.0, -0.5), max: (1.0, 0.5))),
    ),
    command: Slots([(alphabet: [
        (symbol: '+', action: Target(joint: "rail", position: 0.5)),
        (symbol: 'f', action: Force(body: "cart", force: (2.0, 0.0))),
    ])]),
)"#,
    );
    let (s, _) = check(&[&slider, "--samples", "0"]);
    assert!(s.ends_with("actions:\n  0: +: motor set point 0.5 m on slider `rail` (ground -> cart); f: force (2, 0) N on `cart`, held\n"), "{s}");
}

#[test]
fn check_lists_a_mixed_templates_force_and_torque_slots() {
    // slot 0 pushes the puck, slot 1 turns the hinge (tests/library/slot_templates.rs)
    let (s, _) = check(&["tests/scenes/mixed_template.ron", "--samples", "0"]);
    assert!(s.contains("slots (2):\n  0: -0+\n  1: -0+\n"), "{s}");
    assert!(s.contains("actions:\n  0: -: force (-1, 0) N on `puck`, held; 0: nothing; +: force (1, 0) N on `puck`, held\n  1: -: torque -0.01 N·m on hinge `pin` (ground -> rod), held; 0: nothing; +: torque 0.01 N·m on hinge `pin` (ground -> rod), held\n"), "{s}");
}
