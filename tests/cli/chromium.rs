//! The animated SVG pages (physics, grid) and the report pages (run,
//! sweep) in headless Chromium: a screenshot that is not empty and no
//! console error. SKIPPED, with a notice, when no `chromium` (or
//! `chromium-browser`, `google-chrome`) is on the PATH: CI machines do not
//! install it.

use crate::common::temp_path;
use e3d::csv::parse_trials;
use e3d::report::html::run_page;
use e3d::report::motion_svg::{html_page, motion_svg};
use e3d::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |d| d.join(name)))
        .find(|p| p.is_file())
}

fn check(browser: &Path, page: &Path) {
    let shot = page.with_extension("png");
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--window-size=1000,900",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("chromium runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let console: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains("CONSOLE") || l.contains("Uncaught"))
        .collect();
    assert!(console.is_empty(), "console output: {console:?}");
    let size = std::fs::metadata(&shot).map(|m| m.len()).unwrap_or(0);
    assert!(
        size > 5_000,
        "screenshot {} is {size} bytes: {stderr}",
        shot.display()
    );
}

#[test]
fn pages_render_in_headless_chromium() {
    let Some(browser) = chromium() else {
        eprintln!(
            "SKIPPED: no chromium on the PATH (sudo apt-get install -y chromium to run this check)"
        );
        return;
    };
    let dir = temp_path("chromium");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Scene::builtin("arm7").unwrap();
    let mut w = scene.physics_world().unwrap();
    let c = scene.command_space().parse("+0-+0-+").unwrap();
    let m = w.motion(&c).unwrap();
    let anim = dir.join("arm7.html");
    std::fs::write(
        &anim,
        html_page("arm7", &motion_svg(&scene, "+0-+0-+", &m).unwrap()),
    )
    .unwrap();
    check(&browser, &anim);
    let grid = Scene::builtin("two_rooms").unwrap();
    let c = grid.command_space().parse("EEESSEE").unwrap();
    let anim = dir.join("two_rooms.html");
    std::fs::write(
        &anim,
        html_page(
            "two_rooms",
            &e3d::report::motion_svg::grid_motion_svg(&grid, &c).unwrap(),
        ),
    )
    .unwrap();
    check(&browser, &anim);
    let mut csv = String::from("trial,command,effect,reward\n");
    for t in 1..=200 {
        csv.push_str(&format!("{t},NE,{},{}\n", t % 7, t % 2));
    }
    let page = dir.join("report.html");
    std::fs::write(
        &page,
        run_page("t", "", "{}", &parse_trials(&csv).unwrap(), (2, 4), None),
    )
    .unwrap();
    check(&browser, &page);
    let summary = "scene,learner,use_reward,alpha,beta,lambda,eta,epsilon,sessions,h_mean,h_sd,h_ci_low,h_ci_high\n\
                   g,e3d,false,0.3,1,0.03,0.01,,3,0.9,0.01,0.88,0.92\n\
                   g,e3d,false,0.3,10,0.03,0.01,,3,0.8,0.01,0.78,0.82\n";
    let page = dir.join("sweep.html");
    std::fs::write(
        &page,
        e3d::report::html::sweep_page("s", &e3d::csv::Summary::parse(summary).unwrap(), "", &[]),
    )
    .unwrap();
    check(&browser, &page);
    let _ = std::fs::remove_dir_all(&dir);
}
