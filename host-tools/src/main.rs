//! `metamoran`: the command-line front of the host crates. One module per subcommand in
//! [`commands`]; each parses its own `Args` and prints its report through `Display` or JSON.

mod commands;

use clap::{Parser, Subcommand};
use commands::{
    alerts, args::Locations, bench, calibrate, dca1000_emulate, demo, demo_capture, eval, inspect,
    map, odometry, process, provision, record, serve, simulate, site, summarize,
};
use std::process::ExitCode;

/// Metamoran: mmWave radar + camera depth imaging.
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(flatten)]
    locations: Locations,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Summarize(summarize::Args),
    Calibrate(calibrate::Args),
    Process(process::Args),
    Inspect(inspect::Args),
    Odometry(odometry::Args),
    Map(map::Args),
    Eval(eval::Args),
    Simulate(simulate::Args),
    Demo(demo::Args),
    Alerts(alerts::Args),
    Site(site::Args),
    Serve(serve::Args),
    #[command(name = "hash-password")]
    HashPassword(serve::HashArgs),
    #[command(name = "demo-capture")]
    DemoCapture(demo_capture::Args),
    Bench(bench::Args),
    Provision(provision::Args),
    Record(record::Args),
    #[command(name = "dca1000-emulate")]
    Dca1000Emulate(dca1000_emulate::Args),
}

fn run(cli: &Cli) -> commands::Result {
    let at = &cli.locations;
    match &cli.command {
        Command::Summarize(a) => summarize::run(a),
        Command::Calibrate(a) => calibrate::run(a),
        Command::Process(a) => process::run(a, at),
        Command::Inspect(a) => inspect::run(a),
        Command::Odometry(a) => odometry::run(a),
        Command::Map(a) => map::run(a),
        Command::Eval(a) => eval::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Demo(a) => demo::run(a, at),
        Command::Alerts(a) => alerts::run(a),
        Command::Site(a) => site::run(a),
        Command::Serve(a) => serve::run(a),
        Command::HashPassword(a) => serve::hash(a),
        Command::DemoCapture(a) => demo_capture::run(a, at),
        Command::Bench(a) => bench::run(a, at),
        Command::Provision(a) => provision::run(a, at),
        Command::Record(a) => record::run(a),
        Command::Dca1000Emulate(a) => dca1000_emulate::run(a),
    }
}

/// Exit status of a process whose reader went away (128 + SIGPIPE, as a shell reports one).
const BROKEN_PIPE_EXIT: i32 = 141;

fn main() -> ExitCode {
    // `metamoran odometry B | head` closes standard output early; `print!` then panics. Leave
    // quietly as a Unix filter would, instead of reporting that panic.
    let report = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map_or("", String::as_str);
        if message.starts_with("failed printing to stdout") && message.contains("os error 32") {
            std::process::exit(BROKEN_PIPE_EXIT);
        }
        report(info);
    }));
    match run(&Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
