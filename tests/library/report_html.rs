//! `e3d report DIR`'s page: heat map cells early and late, the reward
//! curve, one chart per slot, no script.

use e3d::csv::parse_trials;
use e3d::report::html::run_page;

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
        .0
        .contains("command"));
}

#[test]
fn the_page_has_both_heat_maps_the_reward_and_a_chart_per_slot() {
    let rows = parse_trials(&csv()).unwrap();
    let page = run_page("t", "", "{\"scene\":\"x\"}", &rows, (2, 3), None);
    assert!(page.starts_with("<!DOCTYPE html>"));
    // two heat maps of 2 x 3 cells (no scene: no elite map)
    assert_eq!(page.matches(r#"class="cell""#).count(), 12);
    assert!(page.contains("early: trials 1..10") && page.contains("late: trials 91..100"));
    // early all in effect 0, late all in effect 5
    assert!(page.contains("effect 0 (row 0, col 0): 100.00%"));
    assert!(page.contains("effect 5 (row 1, col 2): 100.00%"));
    assert!(page.contains("cumulative reward"));
    assert!(page.contains("slot 0:") && page.contains("slot 1:") && !page.contains("slot 2:"));
    assert!(!page.contains("<script"));
}

#[cfg(feature = "plots")]
mod sweep {
    use e3d::csv::Summary;
    use e3d::report::html::sweep_page;

    const CSV: &str = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions,failed,normalized_entropy_mean,normalized_entropy_sd,normalized_entropy_ci_low,normalized_entropy_ci_high,first_reward_trial_mean,first_reward_trial_sd,first_reward_trial_ci_low,first_reward_trial_ci_high\n\
two_rooms,e3d,false,0.3,1,0.03,0.003,,2,0,0.8302690281245326,0.02721434585793402,0.585757831635245,1.0747802246138203,,,,\n\
two_rooms,e3d,false,0.3,100,0.03,0.003,,2,1,0.8082385520182234,0.013186851440952906,0.6897593925122136,0.9267177115242331,12.5,3.5,1,40\n\
two_rooms,e3d,false,0.3,1,0.03,0.03,,2,0,0.8271039914527295,0.0019987706445061012,0.8091457497096758,0.8450622331957832,,,,\n\
two_rooms,e3d,false,0.3,100,0.03,0.03,,2,0,0.81,0.01,0.8,0.82,,,,\n\
two_rooms,uniform,false,,,,,,2,0,0.7,0.02,0.6,0.8,,,,\n";

    /// A summary built in code, not read: a missing parameter column or a
    /// short row is refused by the plot, not a panic.
    #[test]
    fn a_summary_built_in_code_without_its_columns_is_refused() {
        use e3d::report::sweep_plot::{plot, PlotSpec};
        let spec = PlotSpec {
            x: "beta".into(),
            y: None,
            metric: "normalized_entropy".into(),
            filters: vec![],
        };
        let mut s = Summary::parse(CSV).unwrap();
        let beta = s.col("beta").unwrap();
        s.columns[beta] = "b".into();
        assert_eq!(
            plot(&s, &spec).unwrap_err().0,
            "the summary has no `beta` column; expected the columns e3d writes"
        );
        let mut s = Summary::parse(CSV).unwrap();
        s.rows[2].truncate(3);
        assert_eq!(
            plot(&s, &spec).unwrap_err().0,
            "row 3 of the summary has 3 fields, expected 18 (one per column)"
        );
    }

    fn page() -> String {
        sweep_page(
            "e3d sweep: t",
            &Summary::parse(CSV).unwrap(),
            "Sweep(name: \"t\")",
            &["the simulation blew up".to_string()],
        )
    }

    #[test]
    fn the_table_holds_every_cell_and_its_exact_numbers() {
        let page = page();
        assert!(page.starts_with("<!DOCTYPE html>"));
        assert!(!page.contains("<script"));
        // one row per cell, plus the header
        assert_eq!(page.matches("<tr>").count(), 6);
        // the columns that vary are named; those that do not are said once
        for h in ["learner", "alpha", "beta", "eta", "sessions", "failed"] {
            assert!(page.contains(&format!("<th>{h}</th>")), "{h}");
        }
        assert!(!page.contains("<th>scene</th>") && !page.contains("<th>epsilon</th>"));
        assert!(page.contains("the same in every cell: scene two_rooms; use_reward false"));
        assert!(page.contains("<th>normalized_entropy<br>mean ± sd</th>"));
        // the exact values, in the tooltip, and the rounded ones shown
        assert!(page.contains("mean 0.8302690281245326, sd 0.02721434585793402, 95% interval [0.585757831635245, 1.0747802246138203]"));
        assert!(page.contains(">0.8303 ± 0.02721</td>"));
        assert!(page.contains("5 cells, 10 sessions (1 failed), 2 metrics"));
        assert!(page.contains("<li>the simulation blew up</li>"));
        assert!(page.contains("<pre>Sweep(name: &quot;t&quot;)</pre>"));
    }

    #[test]
    fn each_varied_parameter_gets_a_plot_per_metric() {
        let page = page();
        assert!(page.contains("<h2>Against beta</h2>") && page.contains("<h2>Against eta</h2>"));
        // alpha takes one value where it is used: no plot against it
        assert!(!page.contains("<h2>Against alpha</h2>"));
        assert!(page.contains("<h3>normalized_entropy against beta</h3>"));
        // 2 parameters x 2 metrics (first_reward_trial has one value)
        assert_eq!(page.matches("<figure class=\"plot\"><svg").count(), 4);
        // a metric with no value where the parameter is used is not drawn
        let csv = CSV.replace(",12.5,3.5,1,40", ",,,,");
        let page = sweep_page("t", &Summary::parse(&csv).unwrap(), "", &[]);
        assert_eq!(page.matches("<figure class=\"plot\"><svg").count(), 2);
        assert!(page
            .contains("not drawn: no cell with a value of eta has a value of first_reward_trial"));
        assert!(!page.contains("<h2>Failures</h2>"));
    }
}

#[test]
fn the_elite_map_shades_each_cell_by_its_least_effort_command() {
    // arm7: cell 3 reached by "+000000" (1.8 N·m) and "00000-0" (0.12),
    // cell 7 by "------+" (4.62: quality 0)
    let csv = "trial,command,effect,reward\n1,+000000,3,0\n2,00000-0,3,0\n3,------+,7,0\n";
    let rows = parse_trials(csv).unwrap();
    let arm = e3d::Scene::builtin("arm7").unwrap();
    let page = run_page("t", "", "{}", &rows, (15, 15), Some(&arm));
    let qd = 1.0 - 0.12 / 4.62;
    assert!(page.contains(&format!("qd_score {qd:.3}")), "{page}");
    assert!(page.contains(&format!("elite quality {qd:.3}")));
    assert!(page.contains("elite quality 0.000"));
    // three_rooms: every command the same effort, no elite map
    let rooms = e3d::Scene::builtin("three_rooms").unwrap();
    let csv = "trial,command,effect,reward\n1,EEEEEEEEE,3,0\n";
    let page = run_page(
        "t",
        "",
        "{}",
        &parse_trials(csv).unwrap(),
        (3, 9),
        Some(&rooms),
    );
    assert!(!page.contains("qd_score"));
}
