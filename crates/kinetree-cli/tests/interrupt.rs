//! Ctrl-C on the long runs: the spawned binary gets SIGINT once its handler is installed (read
//! from `/proc`, so no test waits on a clock), stops, keeps what it has and exits with 130.
#![cfg(target_os = "linux")]

mod common;

use common::*;
use std::process::{Child, Command, Stdio};

/// Starts `kinetree args` with piped output.
fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_kinetree"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the kinetree binary runs")
}

/// Whether process `pid` catches SIGINT (bit 1 of `SigCgt` in `/proc/<pid>/status`); `None`
/// when it has exited.
fn catches_sigint(pid: u32) -> Option<bool> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    if status
        .lines()
        .any(|l| l.starts_with("State:") && l.contains('Z'))
    {
        return None;
    }
    let mask = status.lines().find_map(|l| l.strip_prefix("SigCgt:"))?;
    Some(u64::from_str_radix(mask.trim(), 16).ok()? & 0b10 != 0)
}

/// The CPU time process `pid` has used, in clock ticks (`utime + stime` of `/proc/<pid>/stat`).
fn cpu_ticks(pid: u32) -> u64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    // The fields after the command name (which is in parentheses): state is field 3, utime 14.
    let after = stat.rsplit(')').next().unwrap_or("");
    let fields: Vec<&str> = after.split_whitespace().collect();
    let tick = |k: usize| {
        fields
            .get(k)
            .and_then(|f| f.parse::<u64>().ok())
            .unwrap_or(0)
    };
    tick(11) + tick(12)
}

/// Waits until `child` has installed its Ctrl-C handler, then sends it SIGINT (as a terminal's
/// Ctrl-C does) and collects its output. A run that works for a minute of CPU time without
/// watching for Ctrl-C fails the test (it would otherwise run for hours).
fn interrupt(child: Child) -> std::process::Output {
    interrupt_after(child, 0)
}

/// As [`interrupt`], once the run has also used `ticks` clock ticks of CPU time after
/// installing its handler (so that it has done some work).
fn interrupt_after(mut child: Child, ticks: u64) -> std::process::Output {
    let pid = child.id();
    loop {
        match catches_sigint(pid) {
            Some(true) => break,
            Some(false) => {
                if cpu_ticks(pid) > 6000 {
                    let _ = child.kill();
                    panic!("the run never watched for Ctrl-C");
                }
                std::thread::yield_now();
            }
            None => panic!(
                "the run ended before it watched for Ctrl-C: {:?}",
                child.wait()
            ),
        }
    }
    let start = cpu_ticks(pid);
    while cpu_ticks(pid) < start + ticks {
        std::thread::yield_now();
    }
    let kill = Command::new("kill")
        .args(["-INT", &pid.to_string()])
        .status()
        .expect("kill runs");
    assert!(kill.success());
    child.wait_with_output().expect("the run ends")
}

#[test]
fn simulate_stops_on_ctrl_c_and_writes_what_it_has() {
    let dir = scratch("interrupt-simulate");
    let out = dir.join("traj.json");
    let plot = dir.join("plot.svg");
    // 10⁸ steps: hours of work, so Ctrl-C always arrives mid-run, after half a second of CPU
    // time in the loop.
    let o = interrupt_after(
        spawn(&[
            "simulate",
            &panda(),
            "--duration",
            "1e5",
            "--dt",
            "1e-3",
            "--no-limit",
            "--out",
            out.to_str().unwrap(),
            "--plot",
            plot.to_str().unwrap(),
        ]),
        50,
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    let done: usize = err
        .split("stopped after ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no step count in: {err}"));
    assert!(
        err.contains(&format!("stopped after {done} of 100000000 steps")),
        "{err}"
    );
    assert!(done > 0, "{err}");
    // The report covers the steps done, and both files were written.
    let text = stdout(&o);
    assert!(text.contains(&format!("{done} steps of 0.001 s")), "{text}");
    assert!(
        text.contains("mechanical energy:") && text.contains("final q:"),
        "{text}"
    );
    assert!(text.contains("trajectory written to"), "{text}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let trajectory = doc["trajectory"].as_array().unwrap();
    assert!(!trajectory.is_empty());
    assert_eq!(trajectory[0]["t"], 0.0);
    // The last sample is the state where it stopped.
    let last = trajectory.last().unwrap()["t"].as_f64().unwrap();
    assert!(
        (last - done as f64 * 1e-3).abs() < 1e-9,
        "last sample at t = {last}"
    );
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bench_stops_on_ctrl_c_and_prints_what_it_measured() {
    // 4·10⁸ calls per repetition: far longer than the test.
    let o = interrupt(spawn(&[
        "bench",
        &panda(),
        "--calls",
        "400000000",
        "--repetitions",
        "1",
        "--json",
    ]));
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    let measured: usize = err
        .split("printed the ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count of timings in: {err}"));
    assert!(err.contains("were not measured"), "{err}");
    // The JSON holds exactly the timings measured, each a positive number.
    let doc: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    let timings = doc["ns_per_call"].as_object().unwrap();
    assert_eq!(timings.len(), measured);
    assert!(
        timings
            .values()
            .all(|t| t.as_f64().is_some_and(|t| t > 0.0))
    );
    assert_eq!(doc["model"], "panda");
}
