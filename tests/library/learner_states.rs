//! Every learner's state saved mid-session and loaded back continues with
//! the same bytes as the learner never stopped; bad bytes are refused with
//! a reason.

use e3d::command::CommandSpace;
use e3d::command::ValueSpace;
use e3d::learner::contextual::{ContextTargets, ContextualLearner, PerContext};
use e3d::learner::{
    Archive, ArchiveValues, ClosedLoopE3d, CountBonus, GoalBabbling, GoalBabblingValues, QLearning,
    RelaxedE3d, StateMarginalMatching,
};
use e3d::learner::{E3d, EpsilonGreedy, GaussianE3d, LearnerState, UniformPolicy, UniformValues};
use e3d::{Command, ContinuousLearner, Learner, Outcome, Params, SessionRng, Target};
use rand::SeedableRng;

const EFFECTS: usize = 7;

/// A made-up world: the effect and reward of a command (and the context
/// it leads to, out of 3).
fn outcome(c: &Command) -> (Outcome, usize) {
    let sum: usize = c
        .symbols
        .iter()
        .enumerate()
        .map(|(i, &s)| (i + 2) * s as usize)
        .sum();
    let o = Outcome {
        effect: sum % EFFECTS,
        reward: if sum % 5 == 0 { 1.0 } else { 0.0 },
        point: [0.0, 0.0],
    };
    (o, sum % 3)
}

fn space() -> CommandSpace {
    CommandSpace::new(vec![
        vec!['a', 'b', 'c'],
        vec!['x', 'y'],
        vec!['a', 'b', 'c', 'd'],
    ])
    .unwrap()
}

fn params() -> Params {
    Params {
        epsilon: 0.2,
        ..Params::TASK1
    }
}

/// Runs `n` trials of `l` from `rng`.
fn run<L: Learner>(l: &mut L, rng: &mut SessionRng, n: usize) {
    let mut c = space().first();
    for _ in 0..n {
        l.propose(rng, &mut c);
        l.learn(&c, &outcome(&c).0);
    }
}

/// Saves `l` after 700 trials, loads it, and runs both 500 more trials
/// from the same generator: the same bytes, the same generator after.
fn continues_bit_for_bit<L, F>(mut l: L, run: F) -> usize
where
    L: LearnerState,
    F: Fn(&mut L, &mut SessionRng, usize),
{
    let mut rng = SessionRng::seed_from_u64(11);
    run(&mut l, &mut rng, 700);
    let saved = l.to_bytes();
    let mut back = L::from_bytes(&saved).unwrap();
    assert_eq!(back.to_bytes(), saved, "{}", L::KIND);
    assert_eq!(e3d::learner::state::state_kind(&saved).unwrap(), L::KIND);
    let e = e3d::learner::state::state_kind(&saved[..22]).unwrap_err();
    assert_eq!(e.to_string(), "a learner's state cut before its kind");
    let mut rng2 = rng.clone();
    run(&mut l, &mut rng, 500);
    run(&mut back, &mut rng2, 500);
    assert_eq!(back.to_bytes(), l.to_bytes(), "{}", L::KIND);
    assert_ne!(
        l.to_bytes(),
        saved,
        "{}: 500 trials changed nothing",
        L::KIND
    );
    assert_eq!(rng, rng2);
    assert_eq!(back.shape(), l.shape());
    // cut short, one byte more, or another kind's bytes: refused
    for n in [0, 20, 25, saved.len() / 2, saved.len() - 1] {
        assert!(L::from_bytes(&saved[..n]).is_err(), "{}: {n}", L::KIND);
    }
    let mut long = saved.clone();
    long.push(0);
    let e = L::from_bytes(&long).err().unwrap().to_string();
    assert!(e.contains("1 bytes after the state"), "{e}");
    saved.len()
}

#[test]
fn every_symbol_learner_continues_bit_for_bit_after_a_save() {
    let (s, p) = (space(), params());
    let t = Target::Weights(vec![1.0, 2.0, 3.0, 4.0, 1.0, 1.0, 1.0]);
    continues_bit_for_bit(E3d::new(&s, EFFECTS, &p, &t).unwrap(), run);
    continues_bit_for_bit(RelaxedE3d::new(&s, EFFECTS, &p, &t).unwrap(), run);
    continues_bit_for_bit(CountBonus::new(&s, EFFECTS, &p), run);
    continues_bit_for_bit(EpsilonGreedy::new(&s, &p), run);
    // the learners of kept commands: every cell's command, the choices made
    let n = continues_bit_for_bit(Archive::new(&s, EFFECTS, &p), run);
    assert!(n > 7 * 3, "{n} bytes: the kept commands are saved");
    continues_bit_for_bit(GoalBabbling::new(&s, EFFECTS, &p), run);
    continues_bit_for_bit(e3d::learner::ArchiveReached::new(&s, EFFECTS, &p), run);
    continues_bit_for_bit(e3d::learner::MapElites::new(&s, EFFECTS, &p), run);
    let saved = GoalBabbling::new(&s, EFFECTS, &p).to_bytes();
    let e = Archive::from_bytes(&saved).err().unwrap().to_string();
    assert!(
        e.contains("the bytes hold the state of a `goal_babbling` learner"),
        "{e}"
    );
    let shape = CountBonus::new(&s, EFFECTS, &p).shape();
    assert_eq!(shape.sizes, [3, 2, 4]);
    assert_eq!(shape.effects, Some(EFFECTS));
    assert!(shape.fits(&[3, 2, 4], EFFECTS, None).is_ok());
    let e = shape.fits(&[3, 2, 4], 9, None).unwrap_err();
    assert_eq!(e, "the learner has 7 effects, the scene 9");
    assert!(shape.fits(&[3, 2], EFFECTS, None).is_err());
    assert!(shape.fits(&[3, 2, 4], EFFECTS, Some(1)).is_err());
    assert_eq!(UniformPolicy::new(&s).shape().effects, None);
    // SMM keeps a copy of its policy every 50 trials
    let n = continues_bit_for_bit(
        StateMarginalMatching::new(&s, EFFECTS, &p, &t).unwrap(),
        run,
    );
    assert!(n > 14 * 9 * 8, "{n} bytes: the policies kept are saved");
    // the uniform policy learns nothing: its bytes stay, the generator moves
    let u = UniformPolicy::new(&s);
    let saved = u.to_bytes();
    let mut back = UniformPolicy::from_bytes(&saved).unwrap();
    let (mut r1, mut r2) = (SessionRng::seed_from_u64(1), SessionRng::seed_from_u64(1));
    let (mut c1, mut c2) = (s.first(), s.first());
    for _ in 0..50 {
        back.propose(&mut r1, &mut c1);
        UniformPolicy::new(&s).propose(&mut r2, &mut c2);
        assert_eq!(c1, c2);
    }
    assert!(E3d::from_bytes(&saved)
        .err()
        .unwrap()
        .to_string()
        .contains("the state of a `uniform` learner"));
    assert!(E3d::from_bytes(b"E3D-STATE-1\n").is_err());
}

#[test]
fn continuous_learners_continue_bit_for_bit_after_a_save() {
    let space = ValueSpace::new(vec![(-1.0, 1.0), (0.0, 3.0)]).unwrap();
    let run = |l: &mut dyn ContinuousLearner, rng: &mut SessionRng, n: usize| {
        let mut v = Vec::new();
        for _ in 0..n {
            l.propose(rng, &mut v);
            let cell = ((v[0] + 1.0) * 2.0) as usize + 4 * (v[1] as usize);
            let o = Outcome {
                effect: cell.min(15),
                reward: 0.0,
                point: [v[0], v[1]],
            };
            l.learn(&v, &o);
        }
    };
    let g = GaussianE3d::new(&space, 16, &params(), &Target::Uniform).unwrap();
    continues_bit_for_bit(g, |l, r, n| run(l, r, n));
    let a = ArchiveValues::new(&space, 16, &params());
    continues_bit_for_bit(a, |l, r, n| run(l, r, n));
    let gb = GoalBabblingValues::new(&space, 16, &params());
    assert_eq!(gb.shape().sizes, [0, 0]);
    continues_bit_for_bit(gb, |l, r, n| run(l, r, n));
    let u = UniformValues::new(&space);
    let back = UniformValues::from_bytes(&u.to_bytes()).unwrap();
    assert_eq!(back.shape().sizes, [0, 0]);
    assert_eq!(back.slot_gaussian(1), u.slot_gaussian(1));
}

/// Runs `n` trials of a contextual learner, each in the context the
/// previous one led to, episodes of 4 commands.
fn run_contexts<L: ContextualLearner>(l: &mut L, rng: &mut SessionRng, n: usize) {
    let mut c = space().first();
    let mut context = 0;
    for t in 0..n {
        l.propose(context, rng, &mut c);
        let (o, next) = outcome(&c);
        let next = (t % 4 != 3).then_some(next);
        l.learn(context, &c, &o, next);
        context = next.unwrap_or(0);
    }
}

#[test]
fn contextual_learners_continue_bit_for_bit_after_a_save() {
    let (s, p) = (space(), params());
    let targets = ContextTargets::PerContext(vec![
        Target::Uniform,
        Target::Weights(vec![5.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]),
        Target::Uniform,
    ]);
    let closed = ClosedLoopE3d::new(&s, EFFECTS, 3, &p, &targets, 0.9).unwrap();
    continues_bit_for_bit(closed, run_contexts);
    continues_bit_for_bit(QLearning::new(&s, 3, &p, 0.9).unwrap(), run_contexts);
    let per = |n| PerContext::new((0..n).map(|_| CountBonus::new(&s, EFFECTS, &p)).collect());
    continues_bit_for_bit(per(3), run_contexts);
    let shape = QLearning::new(&s, 3, &p, 0.9).unwrap().shape();
    assert_eq!(
        (shape.sizes, shape.effects, shape.contexts),
        (vec![3, 2, 4], None, Some(3))
    );
    assert_eq!(per(2).shape().contexts, Some(2));
    // a learner per context of another kind, or Q-learning's bytes: refused
    let saved = per(3).to_bytes();
    let e = PerContext::<E3d>::from_bytes(&saved)
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("learners of kind `count`, expected `e3d`"),
        "{e}"
    );
    let q = QLearning::new(&s, 2, &p, 0.5).unwrap().to_bytes();
    assert!(ClosedLoopE3d::from_bytes(&q).is_err());
    // a command space whose slot repeats a symbol: refused (its bytes end
    // with the space's last slot, `a` then `b` (each its length, 1, then
    // its UTF-8), then alpha, epsilon, gamma and the checksum)
    let other = CommandSpace::repeat(3, &['a', 'b']).unwrap();
    let mut bytes = QLearning::new(&other, 2, &p, 0.5).unwrap().to_bytes();
    bytes.truncate(bytes.len() - 8);
    let b = bytes.len() - 3 * 8 - 1;
    assert_eq!(bytes[b - 3..=b], [1, b'a', 1, b'b']);
    bytes[b] = b'a';
    // with its checksum made anew (else the edit is a checksum error)
    bytes.extend(e3d::hash::fnv1a64(&bytes).to_le_bytes());
    let e = QLearning::from_bytes(&bytes).err().unwrap().to_string();
    assert!(
        e.starts_with("state of a `qlearning` learner: command space"),
        "{e}"
    );
}

/// The table `name` of `l`.
fn table<L: LearnerState>(l: &L, name: &str) -> e3d::learner::state::tables::StateTable {
    l.tables().into_iter().find(|t| t.name == name).unwrap()
}

#[test]
fn tables_by_name_read_write_and_refuse() {
    let (s, p) = (space(), params());
    let mut l = E3d::new(&s, EFFECTS, &p, &Target::Uniform).unwrap();
    run(&mut l, &mut SessionRng::seed_from_u64(3), 300);
    // slots of 3, 2 and 4 symbols: rows of 4, NaN past a slot's alphabet
    let q = table(&l, "q");
    assert_eq!(q.shape, [3, 4]);
    assert_eq!(q.values[..3], *l.q(0));
    assert!(q.values[3].is_nan() && q.values[6].is_nan() && q.values[7].is_nan());
    assert_eq!(q.values[8..], *l.q(2));
    assert_eq!(table(&l, "p").values, l.effect_model().probs());
    // written: the padding ignored; the policy is Q's softmax
    let mut rows = vec![
        0.5,
        0.0,
        0.0,
        f64::NAN,
        1.0,
        0.0,
        7.0,
        7.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ];
    l.set_table("q", &rows).unwrap();
    assert_eq!(l.q(1), [1.0, 0.0]);
    let policy = table(&l, "policy");
    assert!((policy.values[4] - 1f64.exp() / (1f64.exp() + 1.0)).abs() < 1e-15);
    // refused, and nothing written: a NaN inside an alphabet, a short table
    let before = l.to_bytes();
    rows[5] = f64::NAN;
    let e = l.set_table("q", &rows).unwrap_err().to_string();
    assert!(
        e.contains("table `q`, slot 1: NaN is not a finite number"),
        "{e}"
    );
    let e = l.set_table("p", &[1.0]).unwrap_err().to_string();
    assert!(e.contains("table `p`: 1 values given, expected 7"), "{e}");
    let e = l.set_table("counts", &[]).unwrap_err().to_string();
    assert!(
        e.contains("a `e3d` learner has no table `counts` (its tables: q, policy, p, target)"),
        "{e}"
    );
    assert_eq!(l.to_bytes(), before);
    // contexts: a first axis; written all or nothing
    let targets = ContextTargets::Shared(Target::Uniform);
    let mut closed = ClosedLoopE3d::new(&s, EFFECTS, 3, &p, &targets, 0.9).unwrap();
    run_contexts(&mut closed, &mut SessionRng::seed_from_u64(4), 200);
    assert_eq!(table(&closed, "q").shape, [3, 3, 4]);
    assert_eq!(table(&closed, "p").shape, [3, EFFECTS]);
    let reference = table(&closed, "reference");
    assert_eq!(reference.shape, [3, 24]);
    assert_eq!(reference.values[24..48], *closed.reference(1));
    let p1 = table(&closed, "p").values[EFFECTS..2 * EFFECTS].to_vec();
    assert_eq!(p1, closed.context_learner(1).effect_model().probs());
    let before = closed.to_bytes();
    let mut t = vec![1.0; 3 * EFFECTS];
    t[2 * EFFECTS] = -1.0; // context 2's target
    let e = closed.set_table("target", &t).unwrap_err().to_string();
    assert!(e.contains("context 2: table `target`"), "{e}");
    assert_eq!(closed.to_bytes(), before);
    t[2 * EFFECTS] = 6.0;
    closed.set_table("target", &t).unwrap();
    assert_eq!(table(&closed, "target").values[2 * EFFECTS], 0.5);
    let ql = QLearning::new(&s, 3, &p, 0.9).unwrap();
    assert_eq!(table(&ql, "q").shape, [3, 24]);
    assert!(UniformPolicy::new(&s).tables().is_empty());
}

/// One trial of `l` on the made-up world, with a terminal point that
/// spreads over the plane (goal babbling and the archive read it).
fn spread_trial<L: Learner>(l: &mut L, rng: &mut SessionRng, c: &mut Command) {
    l.propose(rng, c);
    let (mut o, _) = outcome(c);
    o.point = [o.effect as f64 * 0.3, c.symbols[0] as f64 * 0.7];
    l.learn(c, &o);
}

/// A state with 8 of its bytes overwritten by a NaN, at every offset in
/// turn, is refused or runs on without a panic (a NaN point once loaded
/// and then left goal babbling with no nearest known cell).
#[test]
fn states_holding_a_nan_are_refused_or_run_on() {
    fn check<L: LearnerState + Learner>(mut l: L) {
        let mut rng = SessionRng::seed_from_u64(3);
        let mut c = space().first();
        for _ in 0..200 {
            spread_trial(&mut l, &mut rng, &mut c);
        }
        let saved = l.to_bytes();
        let mut refused = 0;
        for at in 0..saved.len() - 8 {
            let mut b = saved.clone();
            b[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
            let Ok(mut back) = L::from_bytes(&b) else {
                refused += 1;
                continue;
            };
            let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                let mut rng = SessionRng::seed_from_u64(4);
                let mut c = space().first();
                for _ in 0..50 {
                    spread_trial(&mut back, &mut rng, &mut c);
                }
            }));
            assert!(
                ran.is_ok(),
                "{}: a NaN at byte {at} loads, then panics",
                L::KIND
            );
        }
        assert!(refused > 0, "{}: no NaN refused", L::KIND);
    }
    let (s, p) = (space(), params());
    check(GoalBabbling::new(&s, EFFECTS, &p));
    check(Archive::new(&s, EFFECTS, &p));
    check(e3d::learner::MapElites::new(&s, EFFECTS, &p));
    check(CountBonus::new(&s, EFFECTS, &p));
}

/// A state cut short says that its bytes end early, wherever the cut
/// falls: in the body, or in the checksum that ends it.
#[test]
fn a_cut_state_says_its_bytes_end_early() {
    let l = E3d::new(&space(), 18, &params(), &Target::Uniform).unwrap();
    let bytes = l.to_bytes();
    for cut in (1..=8).chain([20, bytes.len() / 2]) {
        let e = E3d::from_bytes(&bytes[..bytes.len() - cut])
            .unwrap_err()
            .to_string();
        assert!(e.contains("end early"), "cut {cut}: {e}");
    }
    // a byte changed is a damaged state, not a cut one
    let mut edited = bytes.clone();
    let at = edited.len() / 2;
    edited[at] ^= 1;
    let e = E3d::from_bytes(&edited).unwrap_err().to_string();
    assert!(e.contains("checksum"), "{e}");
    assert!(E3d::from_bytes(&bytes).is_ok());
}
