//! `e3d scene check --samples N` runs to its end on every shipped scene,
//! for several N (none, one, a few, more than some scenes' commands): no
//! panic (exit 101), and the reach line counts the cells.

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
                assert!(
                    stdout.contains("reach (estimate): ") && stdout.contains(" cells reached"),
                    "{name} {n}: {stdout}"
                );
            }
        }
    }
}
