//! The readers of e3d's own outputs never panic, and what they accept is
//! within bounds: `trials.csv` ([`parse_trials`]), `summary.csv`
//! ([`Summary::parse`], then drawn), a sweep's `journal.txt`
//! ([`journal::read`]), a table file ([`OutcomeTable::read_file`]), and
//! standard input read line by line ([`read_line_bounded`]). Inputs are
//! real files of each kind, mutated with tokens such as `inf`, `NaN`,
//! `4000000000`, quotes, commas and control characters, and arbitrary
//! bytes.
//!
//! A short run is part of the test suite (256 cases per property). A long
//! run: `PROPTEST_CASES=20000 cargo test --release --test library fuzz_outputs::`.

use e3d::csv::parse_trials;
use e3d::csv::Summary;
use e3d::report::sweep_plot::{plot, PlotSpec};
use e3d::sweep::journal;
use e3d::text::{read_line_bounded, Line};
use e3d::{OutcomeTable, Scene};
use proptest::prelude::*;

const TOKENS: &[&str] = &[
    "inf",
    "-inf",
    "NaN",
    "1e308",
    "-1",
    "4000000000",
    "18446744073709551616",
    "\"",
    ",",
    "\n",
    "\r",
    "\x1b",
    "\x07",
    "",
    "0",
    "0.5",
    "e3d",
    "beta",
];

const TRIALS: &str = "trial,command,effect,reward\n1,NESWNES,3,0\n2,EEEEEEE,17,1\n3,SSSSSSS,12,0\n";
const VALUES: &str =
    "trial,values,effect,reward,x,y\n1,\"0.5,-1.2\",3,0,0.1,0.2\n2,\"1,2\",4,1,0.3,0.4\n";
const SUMMARY: &str = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions,h_mean,h_sd,h_ci_low,h_ci_high\n\
g,e3d,false,0.3,1,0.03,0.01,,3,0.9,0.01,0.88,0.92\n\
g,e3d,false,0.3,10,0.03,0.01,,3,0.8,0.01,0.78,0.82\n\
g,uniform,false,,,,,,3,0.7,0.01,0.68,0.72\n";

/// `base` with `edits` applied: (position, token) pairs, each inserting a
/// token or (odd tokens index) replacing the text up to the next comma.
fn mutate(base: &str, edits: &[(usize, usize)]) -> String {
    let mut s = base.to_string();
    for &(at, t) in edits {
        let mut i = at % (s.len() + 1);
        while !s.is_char_boundary(i) {
            i -= 1;
        }
        let tok = TOKENS[t % TOKENS.len()];
        if t % 2 == 1 {
            let end = s[i..].find(',').map_or(s.len(), |k| i + k);
            s.replace_range(i..end, tok);
        } else {
            s.insert_str(i, tok);
        }
    }
    s
}

fn edits() -> impl Strategy<Value = Vec<(usize, usize)>> {
    prop::collection::vec((0usize..400, 0usize..64), 0..6)
}

proptest! {
    #[test]
    fn trials_csv_never_panics_and_what_it_accepts_is_bounded(e in edits(), values in any::<bool>()) {
        let text = mutate(if values { VALUES } else { TRIALS }, &e);
        match parse_trials(&text) {
            Ok(rows) => for r in rows {
                prop_assert!(r.effect < e3d::effect::MAX_EFFECTS);
                prop_assert!(r.reward.is_finite());
                prop_assert!(r.values.iter().all(|v| v.is_finite()));
                prop_assert!(r.command.chars().count() <= 64 && r.values.len() <= 64);
            },
            Err(m) => prop_assert!(m.0.starts_with("trials.csv"), "{}", m),
        }
    }

    #[test]
    fn summary_csv_never_panics_and_draws_only_finite_numbers(e in edits()) {
        let text = mutate(SUMMARY, &e);
        if let Ok(s) = Summary::parse(&text) {
            for r in &s.rows {
                for v in &r[3..] {
                    prop_assert!(v.is_empty() || v.trim().parse::<f64>().is_ok_and(f64::is_finite), "{}", v);
                }
            }
            let spec = PlotSpec { x: "beta".into(), y: None, metric: "h".into(), filters: vec![] };
            if let Ok(svg) = plot(&s, &spec) {
                prop_assert!(!svg.chars().any(|c| c < ' ' && !matches!(c, '\t' | '\n' | '\r')));
            }
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic_a_reader(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse_trials(&text);
        let _ = Summary::parse(&text);
        let mut r = std::io::BufReader::with_capacity(16, &bytes[..]);
        let mut lines = 0;
        loop {
            match read_line_bounded(&mut r, 32).unwrap() {
                Line::End => break,
                Line::Line(l) => prop_assert!(l.len() <= 32 * 3),
                Line::TooLong(l, n) => { prop_assert!(l.len() <= 32 * 3 && n > 32); break }
            }
            lines += 1;
            prop_assert!(lines <= bytes.len() + 1);
        }
    }

    #[test]
    fn journals_and_tables_never_panic(e in edits(), flips in prop::collection::vec((0usize..4000, any::<u8>()), 0..4)) {
        let dir = std::env::temp_dir().join(format!("e3d-fuzz-outputs-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // a journal: the header e3d writes, then mutated lines
        let body = "# e3d sweep journal v1\n# sweep=00000000000000aa shard=1/1 total=2 per_cell=2 scenes= version=0.1.0\n# columns=scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,replicate,seed,h,failure\n";
        let row = "two_rooms,uniform,true,,,,,,0,1,0.5,";
        let line = format!("{:016x} 0,{row}\n", e3d::sweep::fnv1a64(format!("0,{row}").as_bytes()));
        let j = dir.join("journal.txt");
        std::fs::write(&j, mutate(&format!("{body}{line}"), &e)).unwrap();
        let _ = journal::read(&j);
        // a table file with bytes flipped
        let scene = Scene::builtin("two_rooms").unwrap();
        let mut b = OutcomeTable::build_scene(&scene).unwrap().to_bytes(OutcomeTable::key(&scene));
        for &(at, v) in &flips {
            let i = at % b.len();
            b[i] = v;
        }
        let t = dir.join("t.e3dtable");
        std::fs::write(&t, &b).unwrap();
        if let Ok(e3d::world::CachedOutcomes::Full(table)) = OutcomeTable::read_file(&t, &scene) {
            let rewards = scene.reward_table();
            for o in table.outcomes() {
                prop_assert_eq!(o.reward.to_bits(), rewards[o.effect].to_bits());
            }
        }
    }
}
