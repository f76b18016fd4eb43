//! Load a scene and execute a few commands by hand.
//!
//! ```sh
//! cargo run --example execute                       # two_rooms, a few commands
//! cargo run --example execute -- scenes/two_rooms.ron SEEEEES NNNNNNN
//! ```

use e3d::{Outcome, Scene, World};

fn run(scene: &str, commands: &[String]) -> Result<Vec<Outcome>, Box<dyn std::error::Error>> {
    let scene = Scene::resolve(scene)?;
    let mut world = scene.build();
    let space = world.command_space().clone();
    println!(
        "{}: {} slots, {} commands, {} effects",
        scene.spec().name,
        space.num_slots(),
        space
            .num_commands()
            .map_or("too many".into(), |n| n.to_string()),
        world.num_effects()
    );
    let mut rows = Vec::new();
    for text in commands {
        let command = space.parse(text)?;
        let o = world.execute(&command)?;
        println!(
            "{text}: effect {:>3}  reward {}  terminal point ({:.3}, {:.3})",
            o.effect, o.reward, o.point[0], o.point[1]
        );
        rows.push(o);
    }
    Ok(rows)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (scene, commands) = match args.split_first() {
        Some((s, c)) if !c.is_empty() => (s.clone(), c.to_vec()),
        Some((s, _)) => (s.clone(), vec![]),
        None => (
            "two_rooms".to_string(),
            ["EEEEEEE", "SEEEEEE", "SEEEEES", "NNNWWWW"]
                .map(String::from)
                .to_vec(),
        ),
    };
    run(&scene, &commands)?;
    Ok(())
}

#[test]
fn the_door_and_the_reward() {
    let rows = run("two_rooms", &["EEEEEEE".into(), "SEEEEES".into()]).unwrap();
    assert_eq!(rows[0].effect, 2, "the wall stops the agent at (0, 2)");
    assert_eq!(rows[1].effect, 17, "through the door to the corner");
    assert_eq!(rows[1].reward, 1.0);
}
