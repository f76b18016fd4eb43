//! `e3d run` on a scene with start contexts and on closed-loop episodes,
//! and `e3d closed-loop`.

use crate::common::{e3d, ok, stdout_of, temp_dir};

/// two_rooms from two named cells, `a` (0, 0) and `b` (2, 5).
pub(crate) const CONTEXTS: &str = r#"Scene(
    name: "two_rooms_contexts",
    world: Grid(rows: 3, cols: 6, start: (0, 0),
        walls: [((0, 2), (0, 3)), ((2, 2), (2, 3))],
        contexts: [(name: "a", cell: (0, 0)), (name: "b", cell: (2, 5))]),
    command: Repeat(slots: 7, alphabet: [
        (symbol: 'E', action: Move(drow: 0, dcol: 1)),
        (symbol: 'S', action: Move(drow: 1, dcol: 0)),
        (symbol: 'W', action: Move(drow: 0, dcol: -1)),
        (symbol: 'N', action: Move(drow: -1, dcol: 0)),
    ]),
)"#;

/// The normalised entropies printed per start context.
fn entropies(out: &str) -> Vec<f64> {
    let line = out.lines().find(|l| l.starts_with("seed 0:")).unwrap();
    let tail = line.split("per start context: ").nth(1).unwrap();
    tail.split(", ")
        .map(|p| p.split(' ').nth(1).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn run_on_start_contexts_spreads_each_context_and_writes_a_context_column() {
    let dir = temp_dir("contexts-run");
    std::fs::create_dir_all(&*dir).unwrap();
    let scene = dir.join("ctx.ron");
    std::fs::write(&scene, CONTEXTS).unwrap();
    let out = dir.join("out");
    let s = stdout_of(&[
        "run",
        scene.to_str().unwrap(),
        "--trials",
        "4000",
        "--out",
        out.to_str().unwrap(),
    ]);
    let e3d_h = entropies(&s);
    let u = stdout_of(&[
        "run",
        scene.to_str().unwrap(),
        "--trials",
        "4000",
        "--learner",
        "uniform",
    ]);
    let uniform_h = entropies(&u);
    // measured: e3d 0.97-0.98 in each context, uniform about 0.80
    for (a, b) in e3d_h.iter().zip(&uniform_h) {
        assert!(*a > 0.93 && *a > b + 0.1, "{e3d_h:?} vs {uniform_h:?}");
    }
    let csv = std::fs::read_to_string(out.join("trials.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("session,episode,command,context,start,symbols,effect,reward")
    );
    assert_eq!(lines.count(), 4000);
    assert!(csv.contains(",1,b,") && csv.contains(",0,a,"));
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        json.contains("\"start_contexts\": [\n    \"a\",\n    \"b\"\n  ]"),
        "{json}"
    );
    // the report: the scene's grid (recorded), and per start context its
    // episodes, the entropy the run printed, and early and late heat maps
    let r = ok(e3d(&["report", out.to_str().unwrap()]));
    assert!(
        r.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("<h2>Per start context</h2>"));
    let rows: Vec<&str> = page
        .lines()
        .filter(|l| l.starts_with("<tr><td>") && l.contains("class=\"n\""))
        .collect();
    assert_eq!(rows.len(), 2, "{rows:?}");
    let episodes: usize = csv.lines().skip(1).filter(|l| l.contains(",a,")).count();
    for (row, (name, h)) in rows.iter().zip([("a", e3d_h[0]), ("b", e3d_h[1])]) {
        let a_count = if name == "a" {
            episodes
        } else {
            4000 - episodes
        };
        assert!(
            row.starts_with(&format!(
                "<tr><td>{name}</td><td class=\"n\">{a_count}</td><td class=\"n\">{h:.4}</td>"
            )),
            "{row}"
        );
    }
    // two heat maps and two per context (no elite map: a grid scene's
    // commands all have the same effort)
    assert_eq!(page.matches("<svg class=\"heat\"").count(), 2 + 2 * 2);
    assert!(page.contains("a, late: episodes "));
}

#[test]
fn closed_loop_runs_from_the_cli() {
    let s = stdout_of(&[
        "run",
        "four_rooms",
        "--commands",
        "3",
        "--closed-loop",
        "--beta",
        "300",
        "--trials",
        "20000",
        "--seed",
        "3",
    ]);
    // measured: the first reward at episode 8913, 10929 rewards
    assert!(s.contains("learner e3d_closed_loop"), "{s}");
    assert!(
        s.contains("first reward at episode 8913, cumulative reward 10929"),
        "{s}"
    );
    let bad = e3d(&["run", "four_rooms", "--closed-loop", "--learner", "count"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--closed-loop takes"));
    // the open loop has no discount: --gamma alone does nothing, so it is refused
    let alone = e3d(&["run", "four_rooms", "--commands", "3", "--gamma", "0.5"]);
    assert_eq!(alone.status.code(), Some(2));
    let err = String::from_utf8_lossy(&alone.stderr);
    assert!(
        err.contains("required arguments were not provided") && err.contains("--closed-loop"),
        "{err}"
    );
    let out_of_range = e3d(&["run", "four_rooms", "--closed-loop", "--gamma", "5"]);
    assert_eq!(out_of_range.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out_of_range.stderr);
    assert!(
        err.contains("gamma = 5: expected a number in [0, 1]"),
        "{err}"
    );
}

#[test]
fn the_closed_loop_comparison_prints_every_arm() {
    let out = ok(e3d(&[
        "closed-loop",
        "--episodes",
        "300",
        "--seeds",
        "2",
        "--threads",
        "1",
    ]));
    let s = String::from_utf8(out.stdout).unwrap();
    for arm in [
        "e3d_closed_loop",
        "e3d_contextual",
        "e3d_open_loop",
        "qlearning",
        "qlearning_moves",
        "uniform",
    ] {
        assert!(s.contains(&format!("| {arm} | ")), "{s}");
    }
    let bad = e3d(&["closed-loop", "arm7"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("Grid scene"));
}

#[test]
fn scene_check_lists_the_contexts_and_exec_runs_each_command_from_each() {
    let dir = temp_dir("contexts-exec");
    std::fs::create_dir_all(&*dir).unwrap();
    let scene = dir.join("ctx.ron");
    std::fs::write(&scene, CONTEXTS).unwrap();
    let s = stdout_of(&["scene", "check", scene.to_str().unwrap()]);
    assert!(s.contains("start contexts (2): a (0, 0), b (2, 5)"), "{s}");
    let s = stdout_of(&[
        "scene",
        "exec",
        scene.to_str().unwrap(),
        "EEEEESS",
        "SSSSWWW",
    ]);
    assert_eq!(
        s,
        "context,start_row,start_col,command,effect,reward,x,y\n\
         a,0,0,EEEEESS,14,0,2.5,0.5\n\
         b,2,5,EEEEESS,17,0,5.5,0.5\n\
         a,0,0,SSSSWWW,12,0,0.5,0.5\n\
         b,2,5,SSSSWWW,15,0,3.5,0.5\n"
    );
}

/// A physics scene with start contexts: `scene check` lists them, `scene
/// exec` gives a row per context, `run` runs episodes with a policy per
/// context, the same bytes with the context memo on and off.
#[test]
fn physics_start_contexts_check_exec_and_run() {
    let check = stdout_of(&["scene", "check", "scenes/puck_contexts.ron"]);
    assert!(
        check.contains("start contexts (2): room_a (named: puck), room_b (named: puck)"),
        "{check}"
    );
    let exec = stdout_of(&[
        "scene",
        "exec",
        "scenes/puck_contexts.ron",
        "NNNNNNN",
        "WWWWWWW",
    ]);
    let rows: Vec<Vec<&str>> = exec.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0],
        ["context", "command", "effect", "reward", "x", "y"]
    );
    let cells: Vec<(&str, &str, &str)> = rows[1..].iter().map(|r| (r[0], r[1], r[2])).collect();
    assert_eq!(
        cells,
        [
            ("room_a", "NNNNNNN", "0"),
            ("room_b", "NNNNNNN", "5"),
            ("room_a", "WWWWWWW", "0"),
            ("room_b", "WWWWWWW", "15"),
        ]
    );
    let dir = temp_dir("physics-contexts-run");
    let run = |memo: &str, out: &str| {
        let out = dir.join(out);
        let args = [
            "run",
            "scenes/puck_contexts.ron",
            "--trials",
            "300",
            "--sessions",
            "2",
            "--memo-cap",
            memo,
            "--out",
            out.to_str().unwrap(),
        ];
        let s = stdout_of(&args);
        assert_eq!(entropies(&s).len(), 2, "{s}");
        std::fs::read(out.join("trials.csv")).unwrap()
    };
    let memo = run("1000000", "memo");
    assert_eq!(memo, run("0", "live"));
    let csv = String::from_utf8(memo).unwrap();
    assert!(csv
        .lines()
        .skip(1)
        .all(|l| l.contains(",room_a,") || l.contains(",room_b,")));
    assert_eq!(csv.lines().count(), 601);
}

/// `scene check` lists what each start context sets, joints as well as
/// bodies (arm7_poses' contexts set only joints: the list was empty).
#[test]
fn check_lists_the_joints_a_context_sets() {
    let check = stdout_of(&["scene", "check", "scenes/arm7_poses.ron"]);
    assert!(
        check.contains(
            "start contexts (3): straight (named: j1), raised (named: j1), curled (named: j2 j4)"
        ),
        "{check}"
    );
}

/// `run --help` offers --commands for any scene of symbols: episodes run on
/// physics scenes too (`physics_start_contexts_check_exec_and_run`).
#[test]
fn run_help_does_not_restrict_commands_to_grid_scenes() {
    let help = stdout_of(&["run", "--help"]);
    let flag = help.split("--commands").nth(1).unwrap();
    let text = &flag[..flag.find("--observe").unwrap()];
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        text.contains("any scene of symbols, grid or physics"),
        "{text}"
    );
    assert!(!text.contains("(grid scenes;"), "{text}");
}

/// Per-move Q-learning by name: `e3d run --learner qlearning_moves` runs
/// each of the K commands' moves as a command of its own and gives, session
/// for session, the closed-loop comparison's arm `qlearning_moves` (seeds
/// 0..3); `closed_loop.csv` holds the table's figures and intervals.
#[test]
fn per_move_q_learning_by_name_is_the_closed_loop_arm() {
    let dir = temp_dir("moves");
    let cl = dir.join("cl");
    let args = [
        "closed-loop",
        "--episodes",
        "1500",
        "--seeds",
        "3",
        "--threads",
        "1",
    ];
    ok(e3d(&[&args[..], &["--out", cl.to_str().unwrap()]].concat()));
    let sessions = std::fs::read_to_string(cl.join("sessions.csv")).unwrap();
    let arm: Vec<(String, String)> = (sessions.lines())
        .filter_map(|l| l.strip_prefix("qlearning_moves,"))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[1].to_string(), f[2].to_string()) // first reward, cumulative reward
        })
        .collect();
    assert_eq!(arm.len(), 3);
    let run = stdout_of(&[
        "run",
        "four_rooms",
        "--learner",
        "qlearning_moves",
        "--commands",
        "3",
        "--epsilon",
        "0",
        "--trials",
        "1500",
        "--sessions",
        "3",
    ]);
    assert!(
        run.contains("learner qlearning, 1500 episodes of 15 command(s)"),
        "{run}"
    );
    for (seed, (first, reward)) in arm.iter().enumerate() {
        let line =
            format!("seed {seed}: first reward at episode {first}, cumulative reward {reward},");
        assert!(run.contains(&line), "{line}\n{run}");
    }
    // every session rewarded, the mean with its t interval
    let csv = std::fs::read_to_string(cl.join("closed_loop.csv")).unwrap();
    let head: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = (csv.lines())
        .find(|l| l.starts_with("qlearning_moves,"))
        .unwrap()
        .split(',')
        .collect();
    let at = |name: &str| row[head.iter().position(|h| *h == name).unwrap()];
    assert_eq!((at("sessions"), at("rewarded")), ("3", "3"));
    let rewards: Vec<f64> = arm.iter().map(|a| a.1.parse().unwrap()).collect();
    let ci = e3d::report::mean_ci95(&rewards).unwrap();
    assert_eq!(
        at("cumulative_reward_mean").parse::<f64>().unwrap(),
        ci.mean
    );
    assert_eq!(
        at("cumulative_reward_ci95_lo").parse::<f64>().unwrap(),
        ci.lo()
    );
    let last = run.lines().last().unwrap();
    assert!(
        last.starts_with(&format!(
            "mean ± 95% (t) of 3 sessions: cumulative reward {:.1} ± {:.1} |",
            ci.mean, ci.half
        )),
        "{last}"
    );
    assert!(last.contains("3 of 3 rewarded"), "{last}");
    // refused where a move is not one alphabet's, and with --initial out of range
    let bad = e3d(&["run", "arm7", "--learner", "qlearning_moves"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&bad.stderr).contains("takes a scene whose command is `Repeat`")
    );
    let bad = e3d(&[
        "run",
        "four_rooms",
        "--learner",
        "qlearning_moves",
        "--initial",
        "inf",
    ]);
    assert!(
        String::from_utf8_lossy(&bad.stderr).contains("--initial = inf: expected a finite number")
    );
}
