//! `e3d report DIR`'s page: heat map cells early and late, the reward
//! curve, one chart per slot, no script.

use e3d::report::html::{parse_trials, run_page};

fn csv() -> String {
    let mut s = String::from("trial,command,effect,reward\n");
    for t in 1..=100 {
        let (cmd, effect, reward) = if t <= 50 {
            ("NE", 0, 0.0)
        } else {
            ("SE", 5, 1.0)
        };
        s.push_str(&format!("{t},{cmd},{effect},{reward}\n"));
    }
    s
}

#[test]
fn parses_with_and_without_a_session_column() {
    let rows = parse_trials(&csv()).unwrap();
    assert_eq!(rows.len(), 100);
    assert_eq!(rows[99].effect, 5);
    let with = "session,trial,command,effect,reward\n0,1,NE,3,0.5\n";
    let r = parse_trials(with).unwrap();
    assert_eq!(
        (r[0].command.as_str(), r[0].effect, r[0].reward),
        ("NE", 3, 0.5)
    );
    assert!(parse_trials("trial,effect\n1,2\n")
        .unwrap_err()
        .contains("command"));
}

#[test]
fn the_page_has_both_heat_maps_the_reward_and_a_chart_per_slot() {
    let rows = parse_trials(&csv()).unwrap();
    let page = run_page("t", "{\"scene\":\"x\"}", &rows, 2, 3);
    assert!(page.starts_with("<!DOCTYPE html>"));
    // two heat maps of 2 x 3 cells
    assert_eq!(page.matches(r#"class="cell""#).count(), 12);
    assert!(page.contains("early: trials 1..10") && page.contains("late: trials 91..100"));
    // early all in effect 0, late all in effect 5
    assert!(page.contains("effect 0 (row 0, col 0): 100.00%"));
    assert!(page.contains("effect 5 (row 1, col 2): 100.00%"));
    assert!(page.contains("cumulative reward"));
    assert!(page.contains("slot 0:") && page.contains("slot 1:") && !page.contains("slot 2:"));
    assert!(!page.contains("<script"));
}
