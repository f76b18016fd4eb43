//! `e3d scene check`: a scene's summary and the reach of a sample of its
//! commands.

use super::simulate::{say_cost, seconds_text};
use crate::cli::console::{errln, outln};
use crate::cli::{progress, CliResult};
use e3d::scene::physics::{BodyKind, JointKind, PhysicsSpec};
use e3d::scene::{Action, GridSpec, Scene, WorldSpec};
use e3d::world::ReachSample;
use e3d::OutcomeTable;

pub(super) fn check(scene: &Scene) -> CliResult {
    let (grid, spec) = (scene.effect_grid(), scene.spec());
    outln!("scene {}: valid", spec.name);
    if !spec.description.is_empty() {
        outln!("  {}", spec.description);
    }
    match &spec.world {
        WorldSpec::Grid(g) => print_grid(g),
        WorldSpec::Physics(p) => print_physics(scene, p),
    }
    outln!("slots ({}):", spec.num_slots());
    if let e3d::scene::CommandSpec::Continuous(slots) = &spec.command {
        for (i, slot) in slots.iter().enumerate() {
            let ((lo, hi), action) = (slot.range, &slot.action);
            let name = slot
                .name
                .as_deref()
                .map_or(String::new(), |n| format!(" ({n})"));
            outln!("  {i}: a value in [{lo}, {hi}]{name}: {action:?}");
        }
        outln!(
            "distinct commands: infinitely many (continuous: live physics only, no table or memo)"
        );
    } else {
        for (i, alphabet) in spec.slots().enumerate() {
            let syms: String = alphabet.iter().map(|s| s.symbol).collect();
            outln!("  {i}: {syms}");
        }
        let n = scene.command_space().num_commands_text();
        outln!("distinct commands: {n}");
    }
    let ([x0, y0], [x1, y1], rows, cols) = (grid.min, grid.max, grid.rows, grid.cols);
    let n = grid.num_cells();
    outln!("effects: {n} ({rows} x {cols} cells over [{x0}, {x1}] x [{y0}, {y1}])");
    print_rewards(scene, &grid);
    print_actions(scene);
    print_context_starts(scene);
    print_noise(spec);
    Ok(())
}

/// A scene's `noise` section, a line per entry (nothing when it draws
/// nothing: a noise-free scene's check is unchanged).
fn print_noise(spec: &e3d::SceneSpec) {
    use e3d::scene::physics::Spread;
    let WorldSpec::Physics(p) = &spec.world else {
        return;
    };
    let Some(n) = p.active_noise() else {
        return;
    };
    let law = |s: Spread| match s {
        Spread::Gaussian { sd } => format!("N(0, {sd}) cut at 3 sd"),
        Spread::Uniform { half_width } => format!("U(-{half_width}, {half_width})"),
    };
    outln!("noise (drawn anew at every execution, keyed by seed and trial; runs live, no table or memo):");
    if let Some(a) = n.actions {
        outln!("  actions: each slot's action times 1 + {}", law(a));
    }
    for s in &n.starts {
        let (what, name) = match s.joint.is_empty() {
            true => ("body", &s.body),
            false => ("joint", &s.joint),
        };
        let mut parts = Vec::new();
        if let Some(x) = s.position {
            parts.push(format!("x and y (m) + {}", law(x)));
        }
        if let Some(a) = s.angle {
            let field = match s.joint.is_empty() {
                true => "angle (rad)",
                false => "coordinate (rad or m)",
            };
            parts.push(format!("{field} + {}", law(a)));
        }
        outln!("  start of {what} `{name}`: {}", parts.join(", "));
    }
    for b in &n.body_numbers {
        let parts: Vec<String> = (b.spreads().iter())
            .filter_map(|(field, s)| s.map(|s| format!("{field} times 1 + {}", law(s))))
            .collect();
        let when = match b.per {
            e3d::scene::physics::Per::Execution => "",
            e3d::scene::physics::Per::Session => ", drawn once per session",
        };
        outln!("  numbers of body `{}`{when}: {}", b.body, parts.join(", "));
    }
}

/// What each slot's symbols do, a line per slot (scenes of symbols; a
/// continuous slot's line above names its action).
fn print_actions(scene: &Scene) {
    if scene.spec().is_continuous() {
        return;
    }
    let physics = match &scene.spec().world {
        WorldSpec::Physics(p) => Some(p),
        WorldSpec::Grid(_) => None,
    };
    outln!("actions:");
    let lines: Vec<String> = (scene.spec().slots())
        .map(|alphabet| {
            let list: Vec<String> = (alphabet.iter())
                .map(|s| format!("{}: {}", s.symbol, action_text(&s.action, physics)))
                .collect();
            list.join("; ")
        })
        .collect();
    // a run of slots with the same actions is one line, `first-last`
    let mut first = 0;
    for i in 0..lines.len() {
        if i + 1 < lines.len() && lines[i + 1] == lines[i] {
            continue;
        }
        match first == i {
            true => outln!("  {i}: {}", lines[i]),
            false => outln!("  {first}-{i}: {}", lines[i]),
        }
        first = i + 1;
    }
}

/// What `action` does, in words, with its joint's bodies.
fn action_text(action: &Action, physics: Option<&PhysicsSpec>) -> String {
    let joint = |name: &str| {
        let j = physics.and_then(|p| p.joints.iter().find(|j| j.name == name));
        match j {
            Some(j) => {
                let slider = matches!(j.kind, JointKind::Prismatic { .. });
                let what = if slider { "slider" } else { "hinge" };
                (
                    format!("{what} `{name}` ({} -> {})", j.parent, j.child),
                    slider,
                )
            }
            None => (format!("joint `{name}`"), false),
        }
    };
    match action {
        Action::Idle => "nothing".to_string(),
        Action::Move { drow, dcol } => {
            let ns = ["north", "", "south"][(drow.signum() + 1) as usize];
            let ew = ["west", "", "east"][(dcol.signum() + 1) as usize];
            let way = match (ns, ew) {
                ("", "") => "stay".to_string(),
                (a, "") | ("", a) => format!("move {a}"),
                (a, b) => format!("move {a}-{b}"),
            };
            format!("{way} (drow {drow}, dcol {dcol})")
        }
        Action::Torque { joint: j, torque } => {
            format!("torque {torque} N·m on {}, held", joint(j).0)
        }
        Action::Force { body, force } => {
            format!("force ({}, {}) N on `{body}`, held", force.0, force.1)
        }
        Action::Impulse { body, impulse } => {
            format!(
                "impulse ({}, {}) N·s on `{body}`, once",
                impulse.0, impulse.1
            )
        }
        Action::Target { joint: j, angle } => {
            let (name, slider) = joint(j);
            let unit = if slider { "m" } else { "rad" };
            format!("motor set point {angle} {unit} on {name}")
        }
    }
}

/// Where each start context of a physics scene puts its bodies and
/// joints, a line each (a grid context's cell is in the line above).
fn print_context_starts(scene: &Scene) {
    let WorldSpec::Physics(p) = &scene.spec().world else {
        return;
    };
    let pair = |(x, y): (f64, f64)| format!("({x}, {y})");
    for c in &p.contexts {
        let mut parts: Vec<String> = Vec::new();
        for b in &c.bodies {
            let what: Vec<String> = [
                b.position.map(|a| match b.to {
                    Some(to) => format!("at a point drawn in {}..{}", pair(a), pair(to)),
                    None => format!("at {}", pair(a)),
                }),
                b.angle.map(|a| format!("angle {a} rad")),
                b.velocity.map(|v| format!("velocity {} m/s", pair(v))),
                b.angular_velocity
                    .map(|w| format!("angular velocity {w} rad/s")),
            ]
            .into_iter()
            .flatten()
            .collect();
            parts.push(format!("`{}` {}", b.body, what.join(", ")));
        }
        for j in &c.joints {
            let slider = (p.joints.iter().find(|s| s.name == j.joint))
                .is_some_and(|s| matches!(s.kind, JointKind::Prismatic { .. }));
            let unit = if slider { "m" } else { "rad" };
            let what: Vec<String> = [
                j.angle.map(|a| match j.to {
                    Some(to) => format!("drawn in [{a}, {to}] {unit}"),
                    None => format!("at {a} {unit}"),
                }),
                j.velocity.map(|v| format!("rate {v} {unit}/s")),
            ]
            .into_iter()
            .flatten()
            .collect();
            parts.push(format!("joint `{}` {}", j.joint, what.join(", ")));
        }
        let rest = match parts.is_empty() {
            true => "the scene's start".to_string(),
            false => parts.join("; "),
        };
        outln!("start context {}: {rest}", c.name);
    }
}

/// The reachability estimate of `scene check`: `samples` seeded random
/// commands executed, the cells they reach, the reward cells' share, and a
/// warning (stderr) when no sampled command reached a reward cell, with
/// what the full check costs.
pub(super) fn check_reach(scene: &Scene, samples: u64, seed: u64) -> CliResult {
    if samples == 0 {
        return Ok(());
    }
    let n = scene.command_space().num_commands();
    let total = n
        .filter(|_| !scene.spec().is_continuous())
        .map_or(samples, |n| n.min(samples));
    let label = format!("scene check {}", scene.spec().name);
    say_cost(&label, scene, total, 1, 1);
    let sampled = progress::track_control(&label, "commands", total, |control| {
        e3d::world::sample_reach_with(scene, samples, seed, control)
    });
    let s = match sampled {
        Ok(s) => s,
        // the scene is valid; a command that blows up is a finding of the
        // check, not a failure of it
        Err(e) => {
            errln!("warning: scene {}: reach: {e}", scene.spec().name);
            return Ok(());
        }
    };
    let grid = scene.effect_grid();
    let n = match scene.value_space() {
        Some(_) => "infinitely many, drawn uniformly in their ranges".to_string(),
        None => scene.command_space().num_commands_text(),
    };
    let (k, secs) = (s.samples, s.seconds);
    let what = match s.exhaustive {
        true => format!("reach: all {k} commands executed ({secs:.2} s)"),
        false => format!("reach (estimate): {k} random commands of {n} (seed {seed}, {secs:.2} s)"),
    };
    let (reached, cells) = (s.reached_cells(), grid.num_cells());
    outln!("{what}: {reached} of {cells} cells reached");
    print_reward_reach(scene, &s);
    Ok(())
}

/// How often the sampled (or all) commands `s` reach the scene's reward
/// cells, with a warning (stderr) when none does.
fn print_reward_reach(scene: &Scene, s: &ReachSample) {
    let grid = scene.effect_grid();
    let cells = rewarded_cells(scene);
    if cells.is_empty() {
        return;
    }
    let effects: Vec<usize> = cells.iter().map(|&(r, c)| r * grid.cols + c).collect();
    let (hits, k) = (s.hits(&effects), s.samples);
    let pct = 100.0 * (hits as f64 / k as f64);
    if s.exhaustive {
        outln!("reward cells reached by {hits} of {k} commands ({pct:.3}%)");
        if hits == 0 {
            errln!(
                "warning: scene {}: no command reaches a reward cell {cells:?} (every command executed)",
                scene.spec().name
            );
        }
        return;
    }
    outln!("reward cells: estimated probability {pct:.3}% ({hits} of {k} sampled commands)");
    if hits == 0 {
        // the rule of three: with no hit in k draws, p < 3/k at 95%
        let bound = 100.0 * 3.0 / k as f64;
        let (name, full) = (&scene.spec().name, full_check_cost(scene));
        errln!("warning: scene {name}: no sampled command reached a reward cell {cells:?}: it may be unreachable, or rarer than about {bound:.2}% (95% bound); {full}");
    }
}

/// What `scene reward-cell` (every command executed) would cost: the
/// commands it simulates and the cost model's estimate (src/world/plan.rs).
pub(super) fn full_check_cost(scene: &Scene) -> String {
    if scene.spec().is_continuous() {
        return "a full check is not possible: continuous commands cannot be enumerated; sample more with `--samples N`".to_string();
    }
    let (threads, name) = (rayon::current_num_threads(), &scene.spec().name);
    let plan = super::simulate::table_plan(scene);
    match (plan.simulated, plan.table_seconds) {
        (Some(k), Some(_)) => {
            let time = seconds_text(super::simulate::plan_table_seconds(scene, &plan));
            format!("a full check (`e3d scene reward-cell {name}`) simulates {k} commands: about {time} on {threads} thread(s) by the cost model, calibrated here")
        }
        _ => {
            let (n, most) = (
                scene.command_space().num_commands_text(),
                e3d::world::MAX_TABLE_COMMANDS,
            );
            format!("a full check is not possible: {n} commands are too many for `e3d scene reward-cell` (at most {most}); sample more with `--samples N`")
        }
    }
}

/// The cells the scene rewards: those it lists and those of its regions,
/// in order, once each.
pub(super) fn rewarded_cells(scene: &Scene) -> Vec<(usize, usize)> {
    let grid = scene.effect_grid();
    let mut cells: Vec<(usize, usize)> = scene.spec().reward.cells.clone();
    for r in &scene.spec().reward.regions {
        cells.extend(r.cells(&grid));
    }
    cells.sort_unstable();
    cells.dedup();
    cells
}

/// A grid world: its size, start, walls and start contexts.
fn print_grid(g: &GridSpec) {
    let (rows, cols, start, walls) = (g.rows, g.cols, g.start, g.walls.len());
    outln!("world: Grid, {rows} x {cols} cells, start {start:?}, {walls} wall(s)");
    if !g.contexts.is_empty() {
        let list: Vec<String> = (g.contexts.iter())
            .map(|c| match c.to {
                Some(to) => format!("{} {:?}..={to:?}", c.name, c.cell),
                None => format!("{} {:?}", c.name, c.cell),
            })
            .collect();
        outln!("start contexts ({}): {}", g.contexts.len(), list.join(", "));
    }
}

/// A physics world: its start contexts (and warnings, on stderr), its
/// schedule, bodies, joints, effect and symmetry.
fn print_physics(scene: &Scene, p: &PhysicsSpec) {
    if !p.contexts.is_empty() {
        let list: Vec<String> = (p.contexts.iter())
            .map(|c| {
                let kind = if c.is_sampled() { "drawn" } else { "named" };
                // what the context sets: its bodies and its joints, by name
                let set: Vec<&str> = (c.bodies.iter().map(|b| b.body.as_str()))
                    .chain(c.joints.iter().map(|j| j.joint.as_str()))
                    .collect();
                format!("{} ({kind}: {})", c.name, set.join(" "))
            })
            .collect();
        outln!("start contexts ({}): {}", p.contexts.len(), list.join(", "));
    }
    for w in p.warnings() {
        errln!("warning: scene {}: {w}", scene.spec().name);
    }
    let (phase, settle, together) = p.schedule.steps(p.dt);
    let how = match together {
        true => format!("all slots push {phase} steps, then settle {settle}"),
        false => format!("{phase} steps per slot, then settle {settle}"),
    };
    let ((gx, gy), dt) = (p.gravity, p.dt);
    let steps = p.schedule.total_steps(dt, scene.spec().num_slots());
    outln!("world: Physics, gravity ({gx}, {gy}) m/s², dt {dt:.6} s, {steps} step(s) per command ({how})");
    let iterations = p.solver_iterations.unwrap_or(4);
    let default = p.solver_iterations.map_or(", Rapier's default", |_| "");
    outln!("solver: {iterations} iteration(s) per step{default} (`--accuracy` measures what other settings cost and change)");
    print_bodies(p);
    print_joints(p);
    match p.effect.world_point() {
        Some((body, (x, y), _)) => outln!("tracked point: ({x}, {y}) on `{body}`"),
        None => outln!("effect: {}", e3d::report::scene_svg::describe_effect(p)),
    }
    if let Some(sym) = p.symmetry {
        let n = scene.command_space().num_commands_text();
        match OutcomeTable::simulated_commands(scene) {
            Some(k) => outln!(
                "symmetry: {sym:?} (checked): {k} of {n} commands simulated, the others reflected"
            ),
            None => outln!("symmetry: {sym:?} (checked)"),
        }
    }
}

/// The bodies, one line each.
fn print_bodies(p: &PhysicsSpec) {
    outln!("bodies ({}):", p.bodies.len());
    for b in &p.bodies {
        let mass = if b.kind == BodyKind::Dynamic {
            format!(", {:.4} kg", b.mass_kg())
        } else {
            String::new()
        };
        let (name, kind, shape, (x, y), angle) = (&b.name, b.kind, &b.shape, b.position, b.angle);
        outln!("  {name:<12} {kind:?}, {shape:?}{mass}, at ({x}, {y}), angle {angle}");
    }
}

/// The joints, one line each.
fn print_joints(p: &PhysicsSpec) {
    outln!("joints ({}):", p.joints.len());
    for j in &p.joints {
        // a slider's numbers are in m, N/m and N·s/m (its kind is named)
        let (kind, unit, force) = match j.kind {
            e3d::scene::physics::JointKind::Revolute => (String::new(), "rad", "N·m"),
            e3d::scene::physics::JointKind::Prismatic { axis } => {
                (format!(", slider along ({}, {})", axis.0, axis.1), "m", "N")
            }
        };
        let limits = (j.limits).map_or("none".into(), |(a, b)| format!("[{a}, {b}] {unit}"));
        let motor = (j.motor).map_or(String::new(), |m| {
            let (k, d) = (m.stiffness, m.damping);
            format!(", motor {k} {force}/{unit}, {d} {force}·s/{unit}")
        });
        let (name, parent, child, damping) = (&j.name, &j.parent, &j.child, j.damping);
        outln!("  {name:<12} {parent} -> {child}{kind}, limits {limits}, damping {damping} {force}·s/{unit}{motor}");
    }
}

/// The reward's part of `scene check`: its regions and every rewarded cell.
fn print_rewards(scene: &Scene, grid: &e3d::effect::EffectGrid) {
    for r in &scene.spec().reward.regions {
        let ((x0, y0), (x1, y1), cells) = (r.min, r.max, r.cells(grid));
        outln!(
            "reward region `{}`: [{x0}, {x1}] x [{y0}, {y1}], cells {cells:?}",
            r.name
        );
    }
    // every rewarded cell, listed or in a region: one answer
    let cells = rewarded_cells(scene);
    if cells.is_empty() {
        outln!("reward cells: none (the scene declares no reward cell or region)");
    } else {
        let reward = &scene.spec().reward;
        let from = match (reward.cells.is_empty(), reward.regions.len()) {
            (true, 1) => " (from the region above)".to_string(),
            (true, _) => " (from the regions above)".to_string(),
            (false, 0) => String::new(),
            (false, _) => " (listed and from the regions above)".to_string(),
        };
        let note = match &reward.note {
            n if n.is_empty() => String::new(),
            n => format!(" ({n})"),
        };
        outln!(
            "reward cells: {cells:?}{from}, value {}{note}",
            reward.value
        );
    }
}

/// `scene check --accuracy N`: per setting of the solver iterations, how
/// often `samples` seeded random commands land in the converged run's
/// cell and what a command costs (one thread), the scene's own setting
/// marked; a grid scene has none.
pub(super) fn check_accuracy(scene: &Scene, samples: u64, seed: u64) -> CliResult {
    if !matches!(scene.spec().world, WorldSpec::Physics(_)) {
        outln!("accuracy: a grid scene has no solver iterations (its moves are exact)");
        return Ok(());
    }
    let label = format!("accuracy {}", scene.spec().name);
    let rows = progress::track(&label, "settings", 0, |_| {
        e3d::world::accuracy(scene, samples, seed)
    })
    .map_err(crate::cli::CliError::simulation)?;
    let own = rows
        .iter()
        .find(|r| r.scene)
        .map_or(1.0, |r| r.seconds_per_command);
    use e3d::world::{CONVERGED_DT_DIVISOR as DIVISOR, CONVERGED_ITERATIONS as ITERATIONS};
    outln!("accuracy ({samples} random commands, seed {seed}, one thread): the share whose terminal point lands in the cell of the converged run (dt / {DIVISOR}, {ITERATIONS} solver iterations), and what a command costs");
    for r in &rows {
        let (iterations, pct) = (r.iterations, 100.0 * r.in_converged_cell);
        let (cost, ratio) = (
            seconds_text(r.seconds_per_command),
            r.seconds_per_command / own,
        );
        let mark = if r.scene { "  <- the scene's" } else { "" };
        outln!("  solver_iterations: {iterations:<3} {pct:>6.1}% in the converged cell, {cost:>8} a command (x{ratio:.2} the scene's cost){mark}");
    }
    Ok(())
}
