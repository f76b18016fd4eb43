//! Effects of several kinds (`e3d::effect::Binning`): one point bins on its
//! grid exactly as before, numbers on strips, two numbers on a grid, any
//! other product on nested blocks; every layout is an `EffectGrid` whose
//! cells are the effects.

use e3d::effect::EffectGrid;
use e3d::effect::{Axis, Binning, Feature};

#[test]
fn one_point_is_todays_effect_bit_for_bit() {
    // arm7's grid, on a lattice of points inside, on and outside it
    let g = EffectGrid::new(15, 15, [-1.875, -1.875], [1.875, 1.875]).unwrap();
    let b = Binning::point(g.clone()).unwrap();
    assert_eq!(b.layout(), &g);
    assert_eq!(b.num_effects(), 225);
    assert!(b.has_units());
    for i in -50..=50 {
        for j in -50..=50 {
            let p = [i as f64 * 0.041, j as f64 * 0.043];
            let (q, e) = b.locate(&p);
            assert_eq!(q, p);
            assert_eq!(e, g.effect_of(p));
        }
    }
}

#[test]
fn a_pole_angle_by_a_cart_position_is_a_grid_of_the_two() {
    let b = Binning::new(vec![
        Axis::Line {
            bins: 9,
            min: -0.9,
            max: 0.9,
        },
        Axis::Line {
            bins: 7,
            min: -1.4,
            max: 1.4,
        },
    ])
    .unwrap();
    let g = b.layout();
    assert_eq!(
        (g.rows, g.cols, g.min, g.max),
        (9, 7, [-1.4, -0.9], [1.4, 0.9])
    );
    // the angle down the rows, its largest value in row 0; the position across
    assert_eq!(b.locate(&[0.0, 0.0]).1, 4 * 7 + 3);
    assert_eq!(b.locate(&[0.89, 1.39]).1, 6);
    assert_eq!(b.locate(&[-0.89, -1.39]).1, 8 * 7);
    // outside: the nearest end bins
    assert_eq!(b.locate(&[5.0, -5.0]).1, 0);
    assert_eq!(b.locate(&[-5.0, 5.0]).1, 62);
    // reward cells and regions read the layout as a grid, in the features' units
    let c = g.center(0, 0);
    assert!(
        (c[0] + 1.2).abs() < 1e-12 && (c[1] - 0.8).abs() < 1e-12,
        "{c:?}"
    );
}

#[test]
fn one_number_is_a_strip() {
    let b = Binning::new(vec![Axis::Line {
        bins: 12,
        min: -std::f64::consts::PI,
        max: std::f64::consts::PI,
    }])
    .unwrap();
    let g = b.layout();
    assert_eq!((g.rows, g.cols), (1, 12));
    let effects: Vec<usize> = (0..12)
        .map(|k| b.locate(&[-3.0 + k as f64 * 0.52]).1)
        .collect();
    assert_eq!(effects, (0..12).collect::<Vec<_>>());
    assert_eq!(b.locate(&[1.0]).0, [1.0, 0.5]);
}

#[test]
fn the_objects_cell_by_the_hands_cell_nests_blocks() {
    let object = EffectGrid::new(3, 3, [0.0, 0.0], [3.0, 3.0]).unwrap();
    let hand = EffectGrid::new(2, 2, [-1.0, -1.0], [1.0, 1.0]).unwrap();
    let b = Binning::new(vec![Axis::Plane(object.clone()), Axis::Plane(hand.clone())]).unwrap();
    let g = b.layout().clone();
    assert_eq!((g.rows, g.cols), (6, 6));
    assert!(!b.has_units());
    assert_eq!(b.arity(), 4);
    // every pair of cells is one effect, and every effect one pair
    let mut seen = [0; 36];
    for o in 0..9 {
        for h in 0..4 {
            let po = object.center(o / 3, o % 3);
            let ph = hand.center(h / 2, h % 2);
            let (p, e) = b.locate(&[po[0], po[1], ph[0], ph[1]]);
            let (row, col) = (e / 6, e % 6);
            assert_eq!(
                (row / 2, col / 2),
                (o / 3, o % 3),
                "the object's cell is the block"
            );
            assert_eq!(
                (row % 2, col % 2),
                (h / 2, h % 2),
                "the hand's cell within it"
            );
            assert_eq!(p, g.center(row, col));
            seen[e] += 1;
        }
    }
    assert!(seen.iter().all(|&n| n == 1));
}

#[test]
fn features_bin_on_their_axes_and_products_are_bounded() {
    let f = Feature::Joint {
        joint: "slider".into(),
        bins: 5,
        range: (-1.0, 1.0),
    };
    assert_eq!(
        f.axis(),
        Axis::Line {
            bins: 5,
            min: -1.0,
            max: 1.0
        }
    );
    // more than 2^20 effects
    let big = EffectGrid::new(1024, 1024, [0.0, 0.0], [1.0, 1.0]).unwrap();
    assert!(Binning::new(vec![Axis::Plane(big.clone()), Axis::Plane(big)]).is_err());
    assert!(Binning::new(vec![]).is_err());
}
