//! Open sweeps: specs built in code and written back as RON, custom worlds
//! and learners through factories, with the seeds, resume and shards of
//! `e3d sweep`.

use crate::common::temp_path;
use e3d::command::CommandSpace;
use e3d::episode::Observe;
use e3d::learner::LearnerSetup;
use e3d::sweep::{
    DirOptions, Learners, LiveScene, MetricSpec, ParamValues, Scale, Shard, Sweep, SweepSpec,
    Values, Worlds,
};
use e3d::{Command, LearnerKind, Outcome, Scene, World, WorldError};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// Every shipped sweep file, with the folder its scene paths start from.
fn shipped() -> Vec<(PathBuf, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut v = Vec::new();
    for dir in ["scenes/sweeps", "benches/sweeps"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|e| e == "ron") {
                v.push(p);
            }
        }
    }
    v.push(root.join("scripts/slurm/test-sweep.ron"));
    v.sort();
    v.into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            (p, text)
        })
        .collect()
}

#[test]
fn shipped_sweeps_round_trip_through_to_ron() {
    let files = shipped();
    assert!(files.len() >= 4, "{files:?}");
    for (path, text) in files {
        let file = path.display().to_string();
        let spec = SweepSpec::parse(&text, &file).unwrap();
        let written = spec.to_ron();
        assert_eq!(
            SweepSpec::parse(&written, "written.ron").unwrap(),
            spec,
            "{file}"
        );
        // written twice, the same bytes
        assert_eq!(SweepSpec::parse(&written, "w").unwrap().to_ron(), written);
        // the same sweep: same cells, same identities, same seeds
        let base = path.parent();
        let a = Sweep::parse(&text, &file, base).unwrap();
        let b = Sweep::parse(&written, "written.ron", base).unwrap();
        assert_eq!(a.cells(), b.cells(), "{file}");
        assert_eq!(a.sessions(), b.sessions(), "{file}");
        assert_eq!(a.results_header(), b.results_header(), "{file}");
    }
}

#[test]
fn a_spec_built_in_code_is_the_file_that_says_the_same() {
    let text = r#"Sweep(
        name: "paper-small",
        scenes: ["two_rooms"],
        learners: [e3d, uniform, egreedy],
        use_reward: [false, true],
        params: (beta: (scale: Log, from: 1, to: 1000, steps: 4), eta: [0.01, 0.1], epsilon: 0.2),
        sessions: 2,
        trials: 300,
        seed: 2020,
        metrics: [normalized_entropy, cumulative_reward(300), first_reward_trial],
    )"#;
    let built = SweepSpec::new(["two_rooms"], ["e3d", "uniform", "egreedy"], 2, 300)
        .with_name("paper-small")
        .with_use_reward([false, true])
        .with_params(ParamValues {
            beta: Some(Values::log(1.0, 1000.0, 4)),
            eta: Some(Values::list([0.01, 0.1])),
            epsilon: Some(0.2.into()),
            ..Default::default()
        })
        .with_seed(2020)
        .with_metrics([
            MetricSpec::NormalizedEntropy,
            MetricSpec::CumulativeReward(300),
            MetricSpec::FirstRewardTrial,
        ]);
    assert_eq!(SweepSpec::parse(text, "small.ron").unwrap(), built);
    let from_file = Sweep::parse(text, "small.ron", None).unwrap();
    let from_code = Sweep::new(built).unwrap();
    assert_eq!(from_code.file, "<SweepSpec>");
    assert_eq!(from_code.sessions(), from_file.sessions());
    let rows =
        |s: &Sweep| -> Vec<String> { s.run(2).unwrap().iter().map(|r| s.result_row(r)).collect() };
    assert_eq!(rows(&from_code), rows(&from_file));
}

#[test]
fn mistakes_in_a_spec_built_in_code_are_refused_by_name() {
    let err = |spec: SweepSpec| Sweep::new(spec).unwrap_err().to_string();
    let spec = || SweepSpec::new(["two_rooms"], ["e3d"], 2, 100);
    assert_eq!(
        err(spec().with_params(ParamValues {
            eta: Some(Values::list([1.5])),
            ..Default::default()
        })),
        "<SweepSpec>: field `eta`: expected a number in (0, 1], found 1.5"
    );
    assert_eq!(
        err(SweepSpec::new(["two_rooms"], ["e3b"], 2, 100)),
        "<SweepSpec>: field `learners`: expected one of the learners (e3d, uniform, egreedy, e3d_relax, count, smm, goal_babbling, archive, archive_reached, map_elites, qlearning_moves), found `e3b`"
    );
    assert!(err(SweepSpec::new(["two_room"], ["e3d"], 2, 100))
        .starts_with("<SweepSpec>: field `scenes`: expected a scene file (relative to the sweep file) or a built-in scene"));
    assert_eq!(
        err(spec().with_use_reward([])),
        "<SweepSpec>: field `use_reward`: expected [true], [false] or [false, true], found []"
    );
}

/// A name that would break the CSV or the identity is refused when it
/// is registered, before any sweep.
#[test]
#[should_panic(
    expected = "learner `a,b`: a name of ASCII letters, digits and `_`, not starting with a digit"
)]
fn a_learner_name_outside_identifiers_is_refused() {
    let _ = Learners::new().with("a,b", &[], |p, space, n, target| {
        Ok(LearnerSetup::new(LearnerKind::Uniform)
            .params(*p)
            .target(target.clone())
            .symbols(space, n)?)
    });
}

/// A world whose effect is the number of `b` symbols (plus `shift`).
struct CountB {
    space: CommandSpace,
    shift: usize,
}

impl World for CountB {
    fn command_space(&self) -> &CommandSpace {
        &self.space
    }
    fn num_effects(&self) -> usize {
        self.space.num_slots() + 1 + self.shift
    }
    fn execute(&mut self, c: &Command) -> Result<Outcome, WorldError> {
        let n = c.symbols.iter().filter(|&&s| s == 1).count() + self.shift;
        Ok(Outcome {
            effect: n,
            reward: (n == 4) as u8 as f64,
            point: [n as f64, 0.0],
        })
    }
}

fn count_b(shift: usize) -> impl Fn() -> CountB + Send + Sync + 'static {
    move || CountB {
        space: CommandSpace::repeat(4, &['a', 'b']).unwrap(),
        shift,
    }
}

fn blind() -> Learners {
    Learners::builtin().with("blind", &["epsilon"], |p, space, n, target| {
        Ok(LearnerSetup::new(LearnerKind::Egreedy)
            .params(*p)
            .target(target.clone())
            .symbols(space, n)?)
    })
}

#[test]
fn custom_names_are_in_results_identities_and_seeds() {
    let worlds = Worlds::new().with_world("count_b", count_b(0));
    let spec = SweepSpec::new(["count_b"], ["blind", "e3d"], 3, 40)
        .with_params(ParamValues {
            epsilon: Some(Values::list([0.1, 0.5])),
            beta: Some(Values::list([10.0])),
            ..Default::default()
        })
        .with_seed(9);
    let sweep = Sweep::with_factories(spec, &worlds, blind()).unwrap();
    assert_eq!(sweep.cells().len(), 3);
    let id = sweep.identity(&sweep.cells()[1], 2);
    assert_eq!(
        id,
        "scene=count_b;learner=blind;use_reward=true;alpha=-;beta=-;lambda=-;eta=-;epsilon=0.5;session=2"
    );
    let results = sweep.run(2).unwrap();
    assert_eq!(results, sweep.run(1).unwrap());
    let r = &results[5];
    assert_eq!(r.session.seed, e3d::sweep::session_seed(9, &id));
    assert!(sweep
        .result_row(r)
        .starts_with(&format!("count_b,blind,true,,,,,0.5,2,{},", r.session.seed)));
    assert!(sweep
        .result_row(&results[6])
        .starts_with("count_b,e3d,true,0.3,10,0.03,0.01,,0,"));
    // the text written for the folder names the custom learner, and reads
    // back with the same factory (not without it)
    assert!(
        sweep.text.contains("learners: [blind, e3d]"),
        "{}",
        sweep.text
    );
    let back = Sweep::parse_with(&sweep.text, "copy.ron", &worlds, blind()).unwrap();
    assert_eq!(back.spec, sweep.spec);
    let e = Sweep::parse(&sweep.text, "copy.ron", None)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("copy.ron:3:16: unknown variant `blind` for `LearnerKind`"),
        "{e}"
    );
}

#[test]
fn custom_factories_refuse_unknown_names_at_their_place() {
    let worlds = Worlds::new().with_world("count_b", count_b(0));
    let text = "Sweep(\n    scenes: [\"count_c\"],\n    learners: [blind],\n    sessions: 1,\n    trials: 5,\n)";
    let e = Sweep::parse_with(text, "s.ron", &worlds, blind())
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "s.ron:2:14: field `scenes`: expected one of the scenes made by code (count_b), found `count_c` (did you mean `count_b`?)"
    );
    let text = text.replace("count_c", "count_b").replace("blind", "blnd");
    let e = Sweep::parse_with(&text, "s.ron", &worlds, blind())
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "s.ron:3:16: unknown learner `blnd` (did you mean `blind`?); expected one of: e3d, uniform, egreedy, e3d_relax, count, smm, goal_babbling, archive, archive_reached, map_elites, qlearning_moves, blind"
    );
    // the built-in learners keep their words
    let text = text.replace("blnd", "e3b");
    let e = Sweep::parse_with(&text, "s.ron", &worlds, Learners::builtin()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "s.ron:3:16: unknown variant `e3b` for `LearnerKind` (did you mean `e3d`?); expected one of: e3d, uniform, egreedy, e3d_relax, count, smm, goal_babbling, archive, archive_reached, map_elites, qlearning_moves"
    );
}

#[test]
fn a_world_of_another_space_is_refused_naming_both() {
    let worlds = Worlds::new().with_world("count_b", count_b(0));
    let spec = SweepSpec::new(["count_b"], ["uniform"], 1, 5);
    let sweep = Sweep::with_factories(spec, &worlds, Learners::builtin()).unwrap();
    let s = sweep.sessions()[0];
    assert!(sweep.run_session(&s, &mut count_b(0)()).is_ok());
    let mut rooms = Scene::builtin("two_rooms").unwrap().build();
    let e = sweep.run_session(&s, &mut *rooms).unwrap_err().to_string();
    assert_eq!(
        e,
        "session 0 is of scene `count_b`, whose commands are 4 slots of `ab` with 5 effects, but the world's commands are 7 slots of `ESWN` with 18 effects"
    );
    // the same space, other effects: refused too
    let e = sweep
        .run_session(&s, &mut count_b(1)())
        .unwrap_err()
        .to_string();
    assert!(
        e.ends_with("the world's commands are 4 slots of `ab` with 6 effects"),
        "{e}"
    );
}

#[test]
fn custom_sweeps_resume_and_refuse_a_changed_world() {
    let tmp = temp_path("sweep-open");
    let _ = std::fs::remove_dir_all(&tmp);
    let spec = SweepSpec::new(["count_b"], ["blind", "uniform"], 4, 30).with_params(ParamValues {
        epsilon: Some(Values::linear(0.0, 0.3, 4)),
        ..Default::default()
    });
    let sweep = |key: u64| {
        let worlds = Worlds::new().with_scene(LiveScene::new("count_b", count_b(0)).with_key(key));
        Sweep::with_factories(spec.clone(), &worlds, blind()).unwrap()
    };
    let options = |resume, shard| DirOptions {
        threads: 2,
        resume,
        shard,
    };
    let whole = tmp.join("whole");
    let r = sweep(1)
        .run_to_dir(&whole, &options(false, Shard::ALL), |_, _| {})
        .unwrap();
    assert_eq!((r.sessions, r.ran), (20, 20));
    let bytes = std::fs::read(whole.join("results.csv")).unwrap();
    // resumed: nothing to run, the same bytes
    let r = sweep(1)
        .run_to_dir(&whole, &options(true, Shard::ALL), |_, _| {})
        .unwrap();
    assert_eq!((r.resumed, r.ran), (20, 0));
    assert_eq!(std::fs::read(whole.join("results.csv")).unwrap(), bytes);
    // a world that changed (another key) cannot be mixed in
    let e = sweep(2)
        .run_to_dir(&whole, &options(true, Shard::ALL), |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("scene `count_b` changed"), "{e}");
    // shards, merged: the bytes of the whole
    for k in 1..=3 {
        let dir = tmp.join(format!("shard{k}"));
        sweep(1)
            .run_to_dir(&dir, &options(false, Shard { k, n: 3 }), |_, _| {})
            .unwrap();
    }
    let parts: Vec<PathBuf> = (1..=3).map(|k| tmp.join(format!("shard{k}"))).collect();
    e3d::sweep::merge(&parts, &tmp.join("merged")).unwrap();
    assert_eq!(
        std::fs::read(tmp.join("merged/results.csv")).unwrap(),
        bytes
    );
    std::fs::remove_dir_all(&tmp).unwrap();
}

#[test]
fn a_scene_edited_in_code_runs_through_the_executor() {
    // the edited scene gets a table like any scene file: the same rows as
    // the file it was made from, under its new name
    let mut spec = Scene::builtin("two_rooms").unwrap().to_spec();
    spec.name = "rooms_from_code".into();
    let scene = spec.validate().unwrap();
    let notices = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
    let seen = notices.clone();
    let worlds = Worlds::new().with_scene(scene);
    let spec = SweepSpec::new(["rooms_from_code"], ["e3d"], 2, 200);
    let sweep = Sweep::with_factories(spec, &worlds, Learners::builtin())
        .unwrap()
        .with_notices(move |line| seen.lock().unwrap().push(line.to_string()));
    let results = sweep.run(2).unwrap();
    assert!(
        notices.lock().unwrap()[0].starts_with("rooms_from_code: outcome table"),
        "{:?}",
        notices.lock().unwrap()
    );
    assert!(sweep.scenes()[0].scene().is_some());
    let rows: Vec<String> = results.iter().map(|r| sweep.result_row(r)).collect();
    assert!(rows[0].starts_with("rooms_from_code,e3d,true,"), "{rows:?}");
}

// ---------------------------------------------------------------------------
// Any valid spec round-trips
// ---------------------------------------------------------------------------

/// Values of a parameter inside `(lo, hi)`: one number, a list of distinct
/// numbers, or a range whose steps are far apart.
fn values(lo: f64, hi: f64) -> impl Strategy<Value = Values> {
    let at = move |k: u32| lo + (hi - lo) * f64::from(k) / 1000.0;
    prop_oneof![
        (1u32..1000).prop_map(move |k| Values::List(vec![at(k)])),
        proptest::collection::btree_set(1u32..1000, 1..6)
            .prop_map(move |ks| Values::List(ks.into_iter().rev().map(at).collect())),
        (1u32..500, 500u32..1000, 1usize..20, any::<bool>()).prop_map(move |(a, b, steps, log)| {
            Values::Range {
                scale: if log { Scale::Log } else { Scale::Linear },
                from: at(a),
                to: at(b),
                steps,
            }
        }),
    ]
}

fn metrics(trials: usize) -> impl Strategy<Value = Option<Vec<MetricSpec>>> {
    let all = vec![
        MetricSpec::NormalizedEntropy,
        MetricSpec::NormalizedEntropyLast1000,
        MetricSpec::KlToTarget,
        MetricSpec::DistinctEffects,
        MetricSpec::FirstRewardTrial,
    ];
    proptest::option::of(
        (
            proptest::sample::subsequence(all, 0..=5),
            proptest::collection::btree_set(1..=trials, 0..3),
        )
            .prop_filter_map("at least one metric", |(mut m, ts)| {
                m.extend(ts.into_iter().map(MetricSpec::CumulativeReward));
                (!m.is_empty()).then_some(m)
            }),
    )
}

fn spec() -> impl Strategy<Value = SweepSpec> {
    let text = "(?s).{0,12}";
    (
        (text, text, proptest::collection::vec(text, 1..4)),
        proptest::sample::subsequence(vec!["e3d", "uniform", "egreedy"], 1..=3).prop_shuffle(),
        prop_oneof![
            Just(vec![true]),
            Just(vec![false]),
            Just(vec![false, true]),
            Just(vec![true, false])
        ],
        (
            proptest::option::of(values(0.0, 10.0)),
            proptest::option::of(values(0.0, 1000.0)),
            proptest::option::of(values(0.0, 5.0)),
            proptest::option::of(values(0.0, 1.0)),
            proptest::option::of(values(0.0, 1.0)),
        ),
        (1usize..50, 1usize..20_000, any::<u64>()),
    )
        .prop_flat_map(
            |(texts, learners, use_reward, p, (sessions, trials, seed))| {
                metrics(trials).prop_map(move |metrics| SweepSpec {
                    name: texts.0.clone(),
                    description: texts.1.clone(),
                    scenes: texts.2.clone(),
                    learners: learners.iter().map(|s| s.to_string()).collect(),
                    use_reward: use_reward.clone(),
                    axes: Vec::new(),
                    params: ParamValues {
                        alpha: p.0.clone(),
                        beta: p.1.clone(),
                        lambda: p.2.clone(),
                        eta: p.3.clone(),
                        epsilon: p.4.clone(),
                        ..Default::default()
                    },
                    sessions,
                    trials,
                    seed,
                    metrics,
                    // the episode fields, drawn from bits of the seed
                    commands: 1 + (seed % 3) as usize,
                    observe: [
                        None,
                        Some(Observe::State),
                        Some(Observe::StartContext),
                        Some(Observe::Blind),
                    ][(seed >> 3) as usize % 4],
                    closed_loop: seed & 4 != 0,
                    gamma: (seed & 4 != 0 && seed & 32 != 0)
                        .then_some(((seed >> 6) % 101) as f64 / 100.0),
                })
            },
        )
}

proptest! {
    #[test]
    fn any_valid_spec_round_trips_through_to_ron(spec in spec()) {
        // every spec made here is valid: it must read back, equal
        let text = spec.to_ron();
        let back = SweepSpec::parse(&text, "spec.ron");
        prop_assert!(back.is_ok(), "{}\n{}", back.unwrap_err(), text);
        prop_assert_eq!(back.unwrap(), spec, "{}", text);
    }
}

/// A scene made in code becomes a CSV field, a journal entry and terminal
/// text by its name: a name with a control character (ESC, BEL, a tab,
/// NUL), a comma, a quote, or of more than 200 characters is refused as a
/// scene file's name is, with the character's code point; it only
/// refused commas, quotes and line breaks (ESC reached results.csv).
#[test]
fn scenes_made_in_code_with_control_characters_in_their_names_are_refused() {
    let long = "n".repeat(201);
    for (name, found) in [
        ("a\u{1b}]0;t\u{7}b", "U+001B"),
        ("a\u{7}b", "U+0007"),
        ("a\tb", "U+0009"),
        ("a\0b", "U+0000"),
        ("a\u{9b}b", "U+009B"),
        ("a,b", "U+002C"),
        ("a\"b", "U+0022"),
        ("a\nb", "U+000A"),
        (long.as_str(), "found 201"),
    ] {
        let worlds = Worlds::new().with_world(name, count_b(0));
        let spec = SweepSpec::new([name], ["blind"], 1, 5);
        let e = Sweep::with_factories(spec, &worlds, blind())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("field `scenes`") && e.contains(found),
            "{name:?}: {e}"
        );
        assert!(!e.contains(['\u{1b}', '\u{7}', '\0', '\u{9b}']), "{e:?}");
    }
    // a name and description of the sweep (text for people) go to RON
    // escaped, and read back the same
    let odd = "a\u{1b}[31m\u{7}\"\\\n\r\tb";
    let spec = SweepSpec::new(["count_b"], ["blind"], 1, 5)
        .with_name(odd)
        .with_description(odd);
    let text = spec.to_ron();
    assert!(!text.contains(['\u{1b}', '\u{7}', '\r']), "{text}");
    let back = Sweep::parse_with(
        &text,
        "s.ron",
        &Worlds::new().with_world("count_b", count_b(0)),
        blind(),
    )
    .unwrap();
    assert_eq!(back.spec.name, odd);
    assert_eq!(back.spec.description, odd);
}
