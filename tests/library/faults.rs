//! Bad input and faults, round 4 of issue 48, in the library: the one
//! name check, the bound on contexts and its linear checks, binned
//! ranges, loaded learner states. Each test fails on the code before its
//! fix.

use crate::common::grid_with_contexts;
use e3d::command::CommandSpace;
use e3d::effect::EffectGrid;
use e3d::learner::state::STATE_HEADER;
use e3d::learner::{E3d, LearnerState};
use e3d::{Params, Scene, Target};

/// Format characters (a right-to-left override, a zero-width space, a
/// line separator) are refused by the one name check; escape_controls
/// shows the bidirectional controls as code points.
#[test]
fn the_name_check_refuses_format_characters() {
    for bad in [
        "a\u{202e}b",
        "a\u{200b}b",
        "a\u{2028}b",
        "a\u{2066}b",
        "a\u{feff}b",
        " ",
    ] {
        assert!(e3d::text::check_name(bad).is_err(), "{bad:?}");
    }
    assert!(e3d::text::check_name("room_a").is_ok());
    assert!(e3d::text::check_name("é ü 中").is_ok());
    assert_eq!(e3d::text::escape_controls("a\u{202e}b"), "a\\u{202e}b");
    assert_eq!(e3d::text::echo("a\u{2067}b"), "a\\u{2067}b");
}

/// 10^5 grid contexts are refused by the documented bound; 1024 load,
/// and a duplicate name far down the list is found (how long each takes:
/// `cargo bench --bench scale -- bounds`).
#[test]
fn contexts_are_bounded_and_checked_in_linear_time() {
    let list: Vec<String> = (0..100_000)
        .map(|k| format!(r#"(name: "c{k}", cell: ({}, {}))"#, k % 3, k % 6))
        .collect();
    let text = grid_with_contexts(&list.join(", "));
    let e = Scene::parse(&text, "many.ron").unwrap_err().to_string();
    assert!(
        e.starts_with("many.ron:")
            && e.contains("at most 1024 start contexts")
            && e.contains("100000"),
        "{e}"
    );

    let text = grid_with_contexts(&list[..1024].join(", "));
    let s = Scene::parse(&text, "ok.ron").unwrap();
    assert_eq!(e3d::world::start_contexts(&s).len(), 1024);

    // a duplicate name far down the list is found, with its place
    let mut dup = list[..1024].to_vec();
    dup[1000] = r#"(name: "c3", cell: (0, 0))"#.into();
    let e = Scene::parse(&grid_with_contexts(&dup.join(", ")), "dup.ron")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("a distinct, non-empty name for every context") && e.contains("`c3`"),
        "{e}"
    );
}

/// Every binned axis: widths that overflow and bins that cannot be told
/// apart are refused, in effect grids and in features.
#[test]
fn binned_axes_need_finite_distinct_bins() {
    assert!(e3d::effect::check_bins(3, -1.7e308, 1.7e308).is_err());
    assert!(e3d::effect::check_bins(3, 0.0, 5e-324).is_err());
    assert!(e3d::effect::check_bins(1 << 20, 0.0, 1e-303).is_err());
    assert!(e3d::effect::check_bins(7, -1.4, 1.4).is_ok());
    let e = EffectGrid::new(1, 3, [-1.7e308, 0.0], [1.7e308, 1.0]).unwrap_err();
    assert!(e.to_string().contains("overflows to infinity"), "{e}");
    let e = EffectGrid::new(2, 3, [0.0, 0.0], [1.0, 5e-324]).unwrap_err();
    assert!(e.to_string().starts_with("rows:"), "{e}");
    let axis = e3d::effect::Axis::Line {
        bins: 3,
        min: 0.0,
        max: 5e-324,
    };
    assert!(e3d::effect::Binning::new(vec![axis]).is_err());
}

fn e3d_state() -> Vec<u8> {
    let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
    E3d::new(&space, 3, &Params::TASK1, &Target::Uniform)
        .unwrap()
        .to_bytes()
}

/// `body` as a state, with its checksum.
fn sealed(body: &[u8]) -> Vec<u8> {
    [body, &e3d::hash::fnv1a64(body).to_le_bytes()].concat()
}

/// Saved states carry a checksum: a flipped bit is refused; states of
/// versions 1 and 2 (written before the states went through serde) and
/// unknown versions are refused by their number.
#[test]
fn learner_states_are_checksummed_and_versioned() {
    let saved = e3d_state();
    assert!(saved.starts_with(STATE_HEADER));
    assert_eq!(E3d::from_bytes(&saved).unwrap().to_bytes(), saved);
    let mut flipped = saved.clone();
    let k = saved.len() / 2;
    flipped[k] ^= 1;
    let e = E3d::from_bytes(&flipped).unwrap_err().to_string();
    assert!(e.contains("checksum"), "{e}");

    let body = &saved[STATE_HEADER.len()..];
    for v in ["1", "2", "9"] {
        let old = [format!("E3D-LEARNER-STATE {v}\n").as_bytes(), body].concat();
        let e = E3d::from_bytes(&old).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!("a learner's state of format version {v}"))
                && e.contains("this e3d reads version 3 only")
                && e.contains("from before its learner states went through serde") == (v != "9"),
            "{e}"
        );
        let kind = e3d::learner::state::state_kind(&old).unwrap_err();
        assert_eq!(kind.to_string(), e);
    }
}

/// A NaN rate or a NaN table entry is refused when a state is read, also
/// when the checksum was made anew after the edit.
#[test]
fn learner_states_hold_no_nan() {
    let saved = e3d_state();
    let body = saved[..saved.len() - 8].to_vec();
    // E3D's fields end with its four rates: alpha lambda, 1 - alpha
    // lambda, alpha / beta, beta
    let rates_at = body.len() - 4 * 8;
    for (i, v) in [(0, f64::NAN), (3, f64::NAN), (3, 0.0), (2, f64::INFINITY)] {
        let mut b = body.clone();
        let at = rates_at + 8 * i;
        b[at..at + 8].copy_from_slice(&v.to_le_bytes());
        let e = E3d::from_bytes(&sealed(&b)).unwrap_err().to_string();
        assert!(
            e.contains("NaN") || e.contains("finite") || e.contains("beta"),
            "rate {i} = {v}: {e}"
        );
    }
    // a NaN in Q: after the header, the kind (its length, "e3d"), the
    // tables' width (variant 0: 4), the number of slots and of entries
    let mut b = body.clone();
    let q_at = STATE_HEADER.len() + 4 + 3;
    assert_eq!(b[q_at - 3..q_at], [0, 2, 4]);
    b[q_at..q_at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    let e = E3d::from_bytes(&sealed(&b)).unwrap_err().to_string();
    assert!(e.contains("NaN"), "{e}");
    b[q_at..q_at + 8].copy_from_slice(&f64::INFINITY.to_le_bytes());
    let e = E3d::from_bytes(&sealed(&b)).unwrap_err().to_string();
    assert!(
        e.contains("table `q`: finite values, found inf at entry 0"),
        "{e}"
    );
}
