//! A session whose simulation blows up is recorded as failed, with the
//! command that blew up, and the sweep goes on.

use std::process::Command;

const BLOWUP: &str = include_str!("../scenes/blowup.ron");

const SWEEP: &str = r#"Sweep(
    scenes: ["blowup.ron"],
    learners: [uniform],
    use_reward: [false],
    sessions: 12,
    trials: 1,
    seed: 3,
)"#;

#[test]
fn a_blown_up_session_is_recorded_and_the_sweep_goes_on() {
    let dir = std::env::temp_dir().join(format!("e3d-sweep-fail-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("blowup.ron"), BLOWUP).unwrap();
    std::fs::write(dir.join("sweep.ron"), SWEEP).unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args([
            "sweep",
            dir.join("sweep.ron").to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let results = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let rows: Vec<&str> = results.lines().skip(1).collect();
    assert_eq!(rows.len(), 12);
    let failed: Vec<&&str> = rows.iter().filter(|r| !r.ends_with(',')).collect();
    // one trial of the uniform policy: half the commands push the puck
    assert!(!failed.is_empty() && failed.len() < 12, "{results}");
    for r in &failed {
        assert!(r.contains("scene `blowup`"), "{r}");
        assert!(
            r.contains("command `0K`") || r.contains("command `TK`"),
            "{r}"
        );
        assert!(r.contains("max_speed"), "{r}");
    }
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let header: Vec<&str> = summary.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = summary.lines().nth(1).unwrap().split(',').collect();
    let at = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
    assert_eq!(at("sessions"), "12");
    assert_eq!(at("failed"), failed.len().to_string());

    // e3d run on the same scene stops with exit code 4 and names the command
    let o = Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args([
            "run",
            dir.join("blowup.ron").to_str().unwrap(),
            "--learner",
            "uniform",
            "--trials",
            "50",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(4));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("scene `blowup`, command `"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_sweep_naming_a_scene_rapier_would_panic_on_is_refused_before_any_work() {
    let dir = std::env::temp_dir().join(format!("e3d-sweep-overflow-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string("tests/bad_inputs/motor_torque_overflow.ron").unwrap();
    std::fs::write(dir.join("motor.ron"), scene).unwrap();
    std::fs::write(
        dir.join("sweep.ron"),
        SWEEP.replace("blowup.ron", "motor.ron"),
    )
    .unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_e3d"))
        .args([
            "sweep",
            dir.join("sweep.ron").to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("motor.ron:15:95: field `torque`: expected symbol '+': a torque that adds at most 1e6 rad/s"),
        "{err}"
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
