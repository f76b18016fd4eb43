//! The two-room grid of docs/canonical-scenes.md, section 1.

use e3d::{OutcomeTable, Scene, World};

fn two_rooms() -> Box<dyn World + Send> {
    Scene::load("scenes/two_rooms.ron").unwrap().build()
}

fn end(w: &mut dyn World, cmd: &str) -> (usize, usize) {
    let c = w.command_space().parse(cmd).unwrap();
    let e = w.execute(&c).unwrap().effect;
    (e / 6, e % 6)
}

#[test]
fn walls_block_and_the_door_lets_through() {
    let mut w = two_rooms();
    // along row 0: the wall between columns 2 and 3 stops the agent at (0, 2)
    assert_eq!(end(&mut w, "EEEEEEE"), (0, 2));
    // through the door on row 1
    assert_eq!(end(&mut w, "SEEEEEE"), (1, 5));
    // along row 2: the wall again
    assert_eq!(end(&mut w, "SSEEEEE"), (2, 2));
    // into the border: nothing moves
    assert_eq!(end(&mut w, "NNNWWWW"), (0, 0));
    // into room B, then down and back west against the wall from the east side
    assert_eq!(end(&mut w, "SEEESWW"), (2, 3));
    // the rewarded corner
    assert_eq!(end(&mut w, "SEEEEES"), (2, 5));
}

#[test]
fn exactly_nine_commands_reach_the_rewarded_corner() {
    let table = OutcomeTable::build(&mut two_rooms()).unwrap();
    assert_eq!(table.len(), 16384);
    let counts = table.effect_counts();
    assert_eq!(counts[2 * 6 + 5], 9);
    let rewarded: Vec<_> = table.outcomes().filter(|o| o.reward == 1.0).collect();
    assert_eq!(rewarded.len(), 9);
    assert!(rewarded
        .iter()
        .all(|o| o.effect == 17 && o.point == [5.5, 0.5]));
    assert_eq!(counts.iter().sum::<u64>(), 16384);
    // every cell is reachable in 7 moves
    assert!(counts.iter().all(|&c| c > 0));
}
