//! `e3d scene check --samples N` runs to its end on every shipped scene,
//! for several N (none, one, a few, more than some scenes' commands): no
//! panic (exit 101), and the reach line counts the cells of N samples,
//! or of every command when N covers the space.

use crate::common::e3d;

#[test]
fn scene_check_samples_never_panics_on_a_shipped_scene() {
    let scenes: Vec<&str> = e3d::scene::BUILTIN.iter().map(|(n, _)| *n).collect();
    assert!(scenes.contains(&"cart_pole") && scenes.contains(&"arm7_continuous"));
    for name in scenes {
        for n in ["0", "1", "3", "50", "300"] {
            let out = e3d(&["scene", "check", name, "--samples", n]);
            let stderr = String::from_utf8_lossy(&out.stderr);
            let stdout = String::from_utf8_lossy(&out.stdout);
            assert_eq!(
                out.status.code(),
                Some(0),
                "scene check {name} --samples {n}: {stderr}"
            );
            assert!(!stderr.contains("panicked"), "{name} {n}: {stderr}");
            if n != "0" {
                // a sample, or every command when N covers the space
                let reach = stdout
                    .lines()
                    .find(|l| l.starts_with("reach"))
                    .unwrap_or_else(|| panic!("{name} {n}: no reach line: {stdout}"));
                assert!(reach.contains(" cells reached"), "{name} {n}: {reach}");
                assert!(
                    reach.starts_with(&format!("reach (estimate): {n} random"))
                        || reach.starts_with("reach: all "),
                    "{name} {n}: {reach}"
                );
            }
        }
    }
}

#[test]
fn scene_check_samples_are_capped_as_run_trials_are() {
    let out = e3d(&[
        "scene",
        "check",
        "arm7_continuous",
        "--samples",
        "100000000000",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--samples") && stderr.contains("0..=100000000"),
        "{stderr}"
    );
}
