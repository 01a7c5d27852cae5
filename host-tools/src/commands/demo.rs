//! `metamoran demo`: the whole system on a built-in scene, no hardware.

use super::args::{LinkArgs, Locations, NatsArgs};
use metamoran::demo::{DemoEdge, DemoOptions};
use metamoran_operator::mqtt::{MqttConfig, MqttLogin, MqttTls};
use std::path::PathBuf;

/// Where the demo's module runs.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum DemoEdgeArg {
    /// QEMU if it is installed and the firmware builds, else in this process.
    Auto,
    /// The firmware under QEMU (an error if it cannot run).
    Qemu,
    /// The `dsp` pipeline in this process.
    InProcess,
}

impl From<DemoEdgeArg> for DemoEdge {
    fn from(a: DemoEdgeArg) -> Self {
        match a {
            DemoEdgeArg::Auto => Self::Auto,
            DemoEdgeArg::Qemu => Self::Qemu,
            DemoEdgeArg::InProcess => Self::InProcess,
        }
    }
}

/// The whole system on a built-in scene, no hardware: simulated radar frames into the module
/// (firmware under QEMU, or in-process where QEMU is absent), telemetry back, camera fusion,
/// perimeter alerts, operator view; outputs in one folder.
#[derive(clap::Args, Debug)]
#[command(
    mut_arg("dca1000", |a| a.help(
        "Take the radar samples from a live DCA1000 stream arriving at ADDR (this host's \
         address and data port) instead of the simulated capture: the scene's 22 frames are \
         recorded first, then processed with its camera products"
    )),
    after_help = "Examples:\n  metamoran demo\n  metamoran demo --out /tmp/demo --edge in-process\n  metamoran demo --perimeter site.toml --json\n  metamoran demo --mqtt localhost:1883 --sensor gate-east\n  metamoran demo --no-live > operator.txt\n  metamoran demo --dca1000 127.0.0.1:4098   (then: metamoran dca1000-emulate radar.bin --to 127.0.0.1:4098)"
)]
pub struct Args {
    /// Output folder (results.json, depth_0.png, points_0.ply, alerts.jsonl, operator.txt, …).
    #[arg(long, default_value = "demo-out")]
    out: PathBuf,
    /// Where the module runs.
    #[arg(long, value_enum, default_value = "auto")]
    edge: DemoEdgeArg,
    /// Perimeter TOML (zones, restricted classes, confidence, hysteresis); default: built in.
    #[arg(long)]
    perimeter: Option<PathBuf>,
    /// Also publish to this MQTT broker (HOST:PORT): objects at QoS 0, alerts at QoS 1,
    /// retained status with a last will, under metamoran/<sensor>/.
    #[arg(long, value_name = "HOST:PORT")]
    mqtt: Option<String>,
    /// Sensor id for the MQTT topics and client id, and the NATS subjects.
    #[arg(long, default_value = "demo")]
    sensor: String,
    /// TLS to the broker: PEM file of the CA that signs its certificate.
    #[arg(long, value_name = "PEM", requires = "mqtt")]
    mqtt_ca: Option<PathBuf>,
    /// TLS client certificate (PEM chain) for brokers that require one; with --mqtt-key.
    #[arg(long, value_name = "PEM", requires_all = ["mqtt_ca", "mqtt_key"])]
    mqtt_cert: Option<PathBuf>,
    /// The TLS client certificate's private key (PEM).
    #[arg(long, value_name = "PEM", requires = "mqtt_cert")]
    mqtt_key: Option<PathBuf>,
    /// Broker username; the password comes from METAMORAN_MQTT_PASSWORD or
    /// --mqtt-password-file, never the command line.
    #[arg(long, requires = "mqtt")]
    mqtt_user: Option<String>,
    /// File holding the broker password (its first line).
    #[arg(long, value_name = "FILE", requires = "mqtt_user")]
    mqtt_password_file: Option<PathBuf>,
    /// Print JSON instead of the operator view.
    #[arg(long)]
    json: bool,
    /// No live terminal view while frames arrive (it is on when stdout is a terminal and
    /// --json is not given); the final operator view is printed either way.
    #[arg(long)]
    no_live: bool,
    /// Simulate the scene with the camera's instance ids renumbered every frame, as a real
    /// segmenter numbers them: the tracks (and so the alerts) do not depend on them.
    #[arg(long)]
    renumber_instances: bool,
    /// Deliver the frames at the scene's frame rate (2 Hz, 11 s) even without the live view,
    /// as a sensor would.
    #[arg(long)]
    realtime: bool,
    /// A live stream in place of the simulated radar capture.
    #[command(flatten)]
    live_radar: LinkArgs,
    /// The site stream (NATS JetStream).
    #[command(flatten)]
    nats: NatsArgs,
}

/// The broker `broker` with the TLS files and login of `args`.
fn mqtt_config(args: &Args, broker: &str) -> Result<MqttConfig, metamoran::Error> {
    let mut config = MqttConfig::parse(broker, &args.sensor)?;
    config.tls = args.mqtt_ca.as_ref().map(|ca| MqttTls {
        ca: ca.clone(),
        client: args.mqtt_cert.clone().zip(args.mqtt_key.clone()),
    });
    if let Some(user) = &args.mqtt_user {
        let password = super::args::password(
            args.mqtt_password_file.as_deref(),
            "METAMORAN_MQTT_PASSWORD",
            "--mqtt-user",
        )?;
        config.login = Some(MqttLogin::new(user, password));
    }
    Ok(config)
}

/// Runs `metamoran demo`.
///
/// # Errors
/// What failed and what to do (an unwritable folder, a bad perimeter, an unreachable broker).
pub fn run(args: &Args, locations: &Locations) -> super::Result {
    let options = DemoOptions {
        edge: args.edge.into(),
        firmware: locations.firmware().ok(),
        perimeter: args.perimeter.clone(),
        mqtt: args
            .mqtt
            .as_deref()
            .map(|b| mqtt_config(args, b))
            .transpose()?,
        live: !args.json && !args.no_live && std::io::IsTerminal::is_terminal(&std::io::stdout()),
        realtime: args.realtime,
        dca1000: args.live_radar.link()?,
        renumber_instances: args.renumber_instances,
        nats: args.nats.config(&args.sensor)?,
    };
    super::print(&metamoran::demo::run(&args.out, &options)?, args.json)
}
