//! Blown-up simulations are reported, never turned into an effect; the
//! `e3d scene` commands and their exit codes.

use crate::common::{e3d_command, stdout_of, temp_path};
use e3d::{Scene, World, WorldError};

/// A rod on a pivot (no gravity) and a free puck; slot 0 drives the rod
/// with `torque`, slot 1 kicks the puck with `kick` N*s.
fn scene(torque: f64, kick: f64, fast: bool) -> String {
    format!(
        r#"Scene(
    name: "blowup",
    world: Physics(
        bodies: [
            (name: "rod", shape: Cuboid(width: 1.0, height: 0.05), mass: 1.0, position: (0.5, 0.0),
             fast_rotation: {fast}),
            (name: "puck", shape: Ball(radius: 0.1), mass: 1.0, position: (0.0, 3.0)),
        ],
        joints: [(name: "pivot", parent: "ground", child: "rod", child_anchor: (-0.5, 0.0))],
        schedule: Simultaneous(push: 0.5, settle: 0.5),
        effect: (body: "rod", point: (0.5, 0.0),
                 grid: (rows: 2, cols: 2, min: (-1.0, -1.0), max: (1.0, 1.0))),
    ),
    command: Slots([
        (alphabet: [(symbol: '0', action: Idle), (symbol: 'T', action: Torque(joint: "pivot", torque: {torque}))]),
        (alphabet: [(symbol: '0', action: Idle), (symbol: 'K', action: Impulse(body: "puck", impulse: ({kick}, 0.0)))]),
    ]),
)"#
    )
}

fn run(text: &str, cmd: &str) -> Result<e3d::Outcome, WorldError> {
    let s = Scene::parse(text, "blowup.ron").unwrap();
    let mut w = s.build();
    let c = w.command_space().parse(cmd).unwrap();
    w.execute(&c)
}

#[test]
fn a_body_faster_than_max_speed_is_a_divergence() {
    let text = scene(1.0, 1e4, false);
    assert!(run(&text, "T0").is_ok());
    match run(&text, "0K") {
        Err(WorldError::Diverged {
            scene,
            command,
            reason,
        }) => {
            assert_eq!((scene.as_str(), command.as_str()), ("blowup", "0K"));
            assert!(
                reason.contains("above the scene's max_speed 100 m/s"),
                "{reason}"
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_body_at_the_angular_cap_is_a_divergence_unless_allowed() {
    // 100 N*m on a rod of I = 1/3 kg m²: 300 rad/s² reaches Rapier's cap of
    // 45° per step (47 rad/s at 1/60 s) after 0.16 s
    let e = run(&scene(100.0, 1.0, false), "T0").unwrap_err();
    assert!(
        e.to_string().contains("Rapier's cap of 45° per step"),
        "{e}"
    );
    // with fast_rotation the rod may spin that fast
    assert!(run(&scene(100.0, 1.0, true), "T0").is_ok());
}

/// Asserts that `text` contains each of `wants`.
fn assert_contains_all(text: &str, wants: &[&str]) {
    for want in wants {
        assert!(text.contains(want), "missing `{want}` in\n{text}");
    }
}

#[test]
fn scene_check_summarises_arm7() {
    let text = stdout_of(&["scene", "check", "scenes/arm7.ron"]);
    assert_contains_all(
        &text,
        &[
            "bodies (7):",
            "joints (7):",
            "distinct commands: 2187",
            "effects: 225 (15 x 15 cells",
            "reward cells: [(6, 5)]",
            "120 step(s) per command",
            "symmetry: FlipY (checked): 1094 of 2187 commands simulated, the others reflected",
        ],
    );
}

#[test]
fn scene_exec_prints_csv_and_reads_stdin() {
    let out = e3d_command()
        .args(["scene", "exec", "arm7", "0000000", "-++++--"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "command,effect,reward,x,y");
    assert_eq!(lines[1], "0000000,119,0,1.75,0");
    assert!(lines[2].starts_with("-++++--,95,1,"), "{}", lines[2]);

    use std::io::Write;
    let mut child = e3d_command()
        .args(["scene", "exec", "scenes/puck_rooms.ron", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"SEEEEES\nNNNWWWW\n")
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("\nSEEEEES,17,1,") && text.contains("\nNNNWWWW,0,0,"),
        "{text}"
    );
}

#[test]
fn exit_codes_tell_bad_input_from_a_blown_up_simulation() {
    // a command that does not fit: bad input (2)
    let out = e3d_command()
        .args(["scene", "exec", "arm7", "00"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    // a scene mistake: bad input (2), with file:line:col of the field
    let dir = temp_path("physics-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.ron");
    std::fs::write(
        &bad,
        scene(1.0, 1.0, false).replace(
            "mass: 1.0, position: (0.0, 3.0)",
            "mass: 0.0, position: (0.0, 3.0)",
        ),
    )
    .unwrap();
    let out = e3d_command()
        .args(["scene", "check"])
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("bad.ron:7:54: field `mass`: expected body `puck`: a mass > 0"),
        "{err}"
    );
    // a blown-up simulation: 4, after the rows of the commands before it
    let blow = dir.join("blowup.ron");
    std::fs::write(&blow, scene(1.0, 1e4, false)).unwrap();
    let out = e3d_command()
        .args(["scene", "exec"])
        .arg(&blow)
        .args(["T0", "0K", "00"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(4));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("command `0K`: the simulation blew up"),
        "{err}"
    );
    let rows = String::from_utf8(out.stdout).unwrap();
    assert_eq!(rows.lines().count(), 2, "{rows}");
    assert!(rows.lines().nth(1).unwrap().starts_with("T0,"), "{rows}");
    // render writes an SVG with the path
    let svg = dir.join("arm7.svg");
    let out = e3d_command()
        .args(["scene", "render", "arm7", "--command", "-++++--", "--out"])
        .arg(&svg)
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains("<polyline") && text.contains("effect 95"));
    // arm7 declares FlipY: the picture shows its mirror line
    assert!(text.contains("mirror line (FlipY)"), "no mirror line");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn scene_table_computes_writes_then_reads_the_table() {
    let dir = temp_path("scene-table");
    let _ = std::fs::remove_dir_all(&dir);
    let run = || {
        let out = e3d_command()
            .args(["scene", "table", "puck_rooms", "--cache"])
            .arg(&dir)
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    let first = run();
    assert!(
        first.contains("commands in") && first.contains("commands/s"),
        "{first}"
    );
    assert!(first.contains("32 copies per Rapier world"), "{first}");
    assert!(first.contains("written to"), "{first}");
    let second = run();
    assert!(second.contains("read from"), "{second}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `e3d scene reward-cell` applies the rule of docs/canonical-scenes.md and says whether the
/// scene's reward cells agree; on pendulum3 (125 commands, no reward) the
/// rule picks cell (2, 1), reached by 2 commands.
#[test]
fn scene_reward_cell_prints_the_rule_and_its_commands() {
    let text = stdout_of(&["scene", "reward-cell", "pendulum3"]);
    assert_contains_all(
        &text,
        &[
        "scene pendulum3: executed 125 commands in ",
        "reached cells: 32 of 64",
        "rule: farthest reached cell from (0.0000, -0.9000): (2, 1) = effect 17, centre (-0.625, 0.375), 1.4199 m away, reached by 2 command(s)",
        "commands reaching it: aac aad",
        "the scene declares no reward cell; by the rule it would be (2, 1): `reward: (cells: [(2, 1)])`",
        ],
    );
}

/// `e3d scene stats` counts contacts, limits and top speeds over the whole
/// command space, and refuses a grid scene with exit code 2.
#[test]
fn scene_stats_reports_a_physics_scene_and_refuses_a_grid() {
    let text = stdout_of(&["scene", "stats", "pendulum3"]);
    assert_contains_all(
        &text,
        &[
            "scene pendulum3: 125 commands in ",
            "reached cells: 32 of 64",
            "commands bringing two moving bodies into contact: 0 (0.0%)",
            "commands bringing a moving body into contact with a fixed body or wall: 0 (0.0%)",
            "commands pressing a joint against a limit (within 0.01 rad): 0 (0.0%)",
            "top linear speed 8.729 m/s (max_speed 100 m/s); top angular speed 22.59 rad/s",
        ],
    );
    let out = e3d_command()
        .args(["scene", "stats", "two_rooms"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("is for physics scenes; this is a grid scene"));
}

/// `e3d scene stats` counts the commands that bring a moving body against
/// a fixed one (a wall) apart from those that bring two moving bodies
/// together: of a puck's three kicks, only `E` reaches the wall.
#[test]
fn scene_stats_counts_contacts_with_fixed_bodies() {
    let dir = temp_path("stats-wall");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("wall.ron");
    std::fs::write(
        &file,
        r#"Scene(
    name: "wall",
    world: Physics(
        bodies: [
            (name: "wall", kind: Fixed, shape: Cuboid(width: 0.1, height: 2.0), position: (1.0, 0.0)),
            (name: "puck", shape: Ball(radius: 0.2), mass: 1.0),
        ],
        schedule: Sequential(phase: 0.5, settle: 0.5),
        effect: (body: "puck", grid: (rows: 1, cols: 4, min: (-2.0, -1.0), max: (2.0, 1.0))),
    ),
    command: Repeat(slots: 1, alphabet: [
        (symbol: 'E', action: Impulse(body: "puck", impulse: (2.0, 0.0))),
        (symbol: 'W', action: Impulse(body: "puck", impulse: (-1.0, 0.0))),
        (symbol: '0', action: Idle),
    ]),
)"#,
    )
    .unwrap();
    let text = stdout_of(&["scene", "stats", file.to_str().unwrap()]);
    assert_contains_all(
        &text,
        &[
            "commands bringing two moving bodies into contact: 0 (0.0%)\n",
            "commands bringing a moving body into contact with a fixed body or wall: 1 (33.3%)\n",
        ],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `scene check` warns, on standard error, about what is possible but
/// suspicious: here a dynamic body that starts outside the effect grid.
#[test]
fn scene_check_warns_about_a_body_outside_the_effect_grid() {
    let o = e3d_command()
        .args(["scene", "check", "tests/scenes/blowup.ron"])
        .output()
        .unwrap();
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(
        err.trim(),
        "warning: scene blowup: dynamic body `puck` starts at (0, 3), outside the effect grid\n\
         warning: scene blowup: reach: scene `blowup`, command `0K`: the simulation blew up: a body moves at 400.0 m/s, above the scene's max_speed 100 m/s"
    );
    // the shipped scenes' geometry has nothing to warn about (their
    // reward cells are rare by design: the sampled estimate warns on
    // several, see tests/cli/scene_check.rs)
    for s in [
        "puck_rooms",
        "arm7",
        "pendulum3",
        "maze3",
        "three_rooms",
        "arm4_gravity",
    ] {
        let o = e3d_command()
            .args(["scene", "check", s, "--samples", "0"])
            .output()
            .unwrap();
        assert!(o.status.success());
        assert_eq!(String::from_utf8_lossy(&o.stderr), "", "{s}");
    }
}
