//! Options several commands share, and the command-line names of library enums (the libraries
//! do not depend on clap).

use clap::ValueEnum;
use metamoran_bundle::{CameraModels, OpenOptions};
use metamoran_dsp::capture::IqOrder;
use std::net::{IpAddr, SocketAddr};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// I/Q order of a capture's samples.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum IqArg {
    /// I[2k], I[2k+1], Q[2k], Q[2k+1] (the bundle format's order)
    Iiqq,
    /// Q[2k], Q[2k+1], I[2k], I[2k+1] (devices with adcbufCfg sample swap)
    Qqii,
}

impl From<IqArg> for IqOrder {
    fn from(a: IqArg) -> Self {
        match a {
            IqArg::Iiqq => IqOrder::Iiqq,
            IqArg::Qqii => IqOrder::Qqii,
        }
    }
}

/// A TI board whose antenna layout places a TI config's channels.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum BoardArg {
    /// xWR1843BOOST (TX1 half a wavelength up)
    Xwr18xxBoost,
    /// xWR1642BOOST
    Xwr16xxBoost,
    /// IWR6843ISK
    Iwr6843isk,
    /// MMWCAS-RF-EVM, four AWR2243
    MmwcasRfEvm,
}

impl From<BoardArg> for metamoran_bundle::ti::Board {
    fn from(a: BoardArg) -> Self {
        match a {
            BoardArg::Xwr18xxBoost => Self::Xwr18xxBoost,
            BoardArg::Xwr16xxBoost => Self::Xwr16xxBoost,
            BoardArg::Iwr6843isk => Self::Iwr6843Isk,
            BoardArg::MmwcasRfEvm => Self::MmwcasRfEvm,
        }
    }
}

/// A processing method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// Camera-guided shape correlation with clutter cancellation, then depth imaging.
    Metamoran,
    /// Strongest range–azimuth reflector inside the mask's azimuth span.
    Naive,
    /// The closest masked monocular depth point.
    Monocular,
}

impl From<ModeArg> for metamoran_process::Mode {
    fn from(a: ModeArg) -> Self {
        match a {
            ModeArg::Metamoran => Self::Metamoran,
            ModeArg::Naive => Self::Naive,
            ModeArg::Monocular => Self::Monocular,
        }
    }
}

/// A scene preset of the simulator.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum PresetArg {
    /// Static, cluttered parking lot; cars, people and signs at 3–60 m.
    ParkingLot,
    /// Static cars at 10–90 m among clutter.
    LongRange,
    /// Moving car, person or sign at 20–300 m among static clutter.
    Moving,
    /// Far movers among static clutter: cars at 100–300 m, people at 100–230 m.
    FarMoving,
    /// A perimeter over 22 frames: a parked car and a person walking into a zone and out (the
    /// demo scene).
    Perimeter,
    /// Multi-object tracking: 30 frames of two people whose walks cross and a slow car.
    Crossing,
    /// Three poles with overlapping coverage watching one site (two people crossing, a car):
    /// OUT/site-<seed>/ holds site.toml and one bundle per pole.
    Site,
    /// The radar on a vehicle driving down a street, 20 frames at 10 Hz, with an elevated TX:
    /// dense radar mapping's scenes.
    Drive,
    /// The drive preset's vehicle in a road tunnel: close walls and a ceiling (issue #21).
    Tunnel,
    /// The drive preset's vehicle crossing an open parking area: rows of parked cars, lamp
    /// posts, building fronts far off (issue #21).
    ParkingArea,
    /// The drive preset's vehicle through a covered car park: a low ceiling over columns and
    /// parked cars (issue #21).
    Garage,
    /// A calibration capture: a corner reflector at 5 m on boresight (for `calibrate`).
    Corner,
}

impl PresetArg {
    /// The single-sensor scene preset (`None` for the multi-pole site).
    pub fn scene(self) -> Option<metamoran_sim::layout::Preset> {
        use metamoran_sim::layout::Preset;
        Some(match self {
            PresetArg::ParkingLot => Preset::ParkingLot,
            PresetArg::LongRange => Preset::LongRange,
            PresetArg::Moving => Preset::Moving,
            PresetArg::FarMoving => Preset::FarMoving,
            PresetArg::Perimeter => Preset::Perimeter,
            PresetArg::Crossing => Preset::Crossing,
            PresetArg::Drive => Preset::Drive,
            PresetArg::Tunnel => Preset::Tunnel,
            PresetArg::ParkingArea => Preset::ParkingArea,
            PresetArg::Garage => Preset::Garage,
            PresetArg::Corner => Preset::Corner,
            PresetArg::Site => return None,
        })
    }
}

/// A simulated radar board.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RadarArg {
    /// xWR18xx-like: 2 TX × 4 RX, 8 virtual elements, 256 samples.
    Xwr18xx,
    /// Cascade-like (MMWCAS): 12 TX × 16 RX, 86 distinct virtual elements, 512 samples.
    Cascade,
    /// The MMWCAS-RF-EVM in TI's layout (chirp order, raised TX, RX by device), written as the
    /// board's four device files.
    Mmwcas,
    /// The drive preset's 4D imaging board: 12 TX × 16 RX as a T, 64 elements in azimuth (1.8°)
    /// and nine rows in elevation (4.2°).
    Imaging,
}

impl From<RadarArg> for metamoran_sim::radar::RadarKind {
    fn from(a: RadarArg) -> Self {
        match a {
            RadarArg::Xwr18xx => Self::Xwr18xx,
            RadarArg::Cascade => Self::Cascade,
            RadarArg::Mmwcas => Self::Mmwcas,
            RadarArg::Imaging => Self::Imaging,
        }
    }
}

/// Camera models that compute a bundle's products from `camera/F_image.png`.
#[derive(clap::Args, Debug)]
pub struct ModelArgs {
    /// ONNX semantic segmenter: input [1,3,H,W] RGB 0..1, output [1,C,H,W] class scores,
    /// labels in its metadata 'labels' or MODEL.labels; replaces F_mask.png and
    /// F_instances.json (connected regions of each class). Needs a build with --features onnx.
    #[arg(long, value_name = "MODEL.onnx")]
    pub segmenter: Option<PathBuf>,
    /// ONNX monocular depth network: input [1,3,H,W] RGB 0..1, output [1,1,H,W] metres along
    /// z; replaces F_depth.png. Needs a build with --features onnx.
    #[arg(long, value_name = "MODEL.onnx")]
    pub depth_model: Option<PathBuf>,
}

/// How to read a bundle: the I/Q order and the camera models.
#[derive(clap::Args, Debug)]
pub struct BundleArgs {
    /// I/Q order of radar.bin.
    #[arg(long, value_enum, default_value = "iiqq")]
    pub iq_order: IqArg,
    #[command(flatten)]
    pub models: ModelArgs,
}

impl BundleArgs {
    /// Bundle options with these models loaded.
    ///
    /// # Errors
    /// A model that cannot be loaded.
    pub fn options(&self) -> Result<OpenOptions, metamoran_bundle::error::InputError> {
        Ok(OpenOptions {
            iq_order: self.iq_order.into(),
            camera_models: CameraModels::load(
                self.models.segmenter.as_deref(),
                self.models.depth_model.as_deref(),
            )?,
            capture: None,
        })
    }
}

/// Where the data and the firmware are, for a `metamoran` run outside a checkout.
#[derive(clap::Args, Debug, Clone)]
pub struct Locations {
    /// The shared data folder (real captures); default: `shared/` beside the checkout this is
    /// run from.
    #[arg(long, global = true, env = "METAMORAN_SHARED", value_name = "DIR")]
    pub shared: Option<PathBuf>,
    /// The firmware's Cargo workspace, built for QEMU runs; default: `firmware/` of the checkout
    /// this is run from.
    #[arg(long, global = true, env = "METAMORAN_FIRMWARE", value_name = "DIR")]
    pub firmware: Option<PathBuf>,
}

impl Locations {
    /// The shared data folder: `--shared`, else the first `shared/` beside the current folder
    /// or one of its parents.
    ///
    /// # Errors
    /// Neither found.
    pub fn shared(&self) -> Result<PathBuf, String> {
        self.shared
            .clone()
            .or_else(metamoran::find_shared)
            .ok_or_else(|| {
                "the shared data folder was not found: give --shared DIR or set METAMORAN_SHARED"
                    .to_owned()
            })
    }

    /// The firmware workspace: `--firmware`, else `firmware/` of the checkout.
    ///
    /// # Errors
    /// Neither found.
    pub fn firmware(&self) -> Result<PathBuf, String> {
        self.firmware
            .clone()
            .or_else(metamoran_edge::qemu::find_firmware)
            .ok_or_else(|| {
                "the firmware sources were not found: give --firmware DIR (the firmware/ folder of a Metamoran checkout) or set METAMORAN_FIRMWARE"
                    .to_owned()
            })
    }
}

/// How to read a capture given on the command line: a bundle folder, or a bare DCA1000 `.bin`
/// with its radar config (shared by the commands that read one).
#[derive(clap::Args, Clone, Debug)]
pub struct CaptureArgs {
    /// Radar config of a bare .bin: a TOML `[radar]` table as in scene.toml, an mmWave SDK .cfg
    /// or an mmWave Studio .mmwave.json.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// The TI board a .cfg or .mmwave.json configures (its antenna layout).
    #[arg(long, value_enum)]
    pub board: Option<BoardArg>,
    /// I/Q order of the samples [default: what a TI config sets, else iiqq].
    #[arg(long, value_enum)]
    pub iq_order: Option<IqArg>,
}

impl CaptureArgs {
    /// Opens `path`: a bare capture with `--config`, else the radar file of a bundle folder
    /// (the bundle checked, its calibration applied).
    ///
    /// # Errors
    /// A message naming the file when it is missing or does not fit its config.
    pub fn open(&self, path: &Path) -> Result<metamoran_bundle::RadarFile, String> {
        if !path.exists() {
            return Err(format!(
                "{}: no such file or folder; give a bundle folder or a DCA1000 .bin",
                path.display()
            ));
        }
        let order = self.iq_order.map(IqOrder::from);
        match &self.config {
            Some(cfg) => {
                metamoran_bundle::capture::open_bare(path, cfg, order, self.board.map(Into::into))
                    .map_err(|e| e.to_string())
            }
            None if path.is_dir() => {
                let open = OpenOptions::iq(order.unwrap_or_default());
                let bundle =
                    metamoran_bundle::Bundle::open(path, open).map_err(|e| e.to_string())?;
                Ok(bundle.into_radar())
            }
            None => Err(format!(
                "{}: a bare capture needs its radar config: add --config radar.toml (a [radar] table as in scene.toml), an mmWave SDK .cfg or an mmWave Studio .mmwave.json",
                path.display()
            )),
        }
    }
}

/// A live DCA1000 stream as the radar input (shared by the commands that take one).
#[derive(clap::Args, Clone, Debug)]
pub struct LinkArgs {
    /// Take the radar samples from a live DCA1000 stream: this host's address and data port the
    /// board sends to (192.168.33.30:4098 on TI's default setup). The address listened on is
    /// printed on stderr once bound (with port 0, the one the OS chose).
    #[arg(long, value_name = "ADDR")]
    pub dca1000: Option<SocketAddr>,
    /// The board's IP: packets from elsewhere are dropped and counted.
    #[arg(long, requires = "dca1000")]
    pub from: Option<IpAddr>,
    /// Configure and start the board over its config port first (connect, FPGA and packet
    /// configuration, start record), stop it at the end; needs --from.
    #[arg(long, requires = "from")]
    pub control: bool,
    /// Seconds to wait for the stream's first packet.
    #[arg(long, default_value_t = 10.0, value_name = "S")]
    pub start_s: f64,
    /// Seconds without a packet that end the stream.
    #[arg(long, default_value_t = 1.0, value_name = "S")]
    pub idle_s: f64,
}

impl LinkArgs {
    /// The stream, if `--dca1000` was given.
    ///
    /// # Errors
    /// A negative or non-finite number of seconds.
    pub fn link(&self) -> Result<Option<metamoran::live::Link>, String> {
        let seconds = |s: f64, flag: &str| {
            Duration::try_from_secs_f64(s).map_err(|_| format!("{flag} {s}: give seconds ≥ 0"))
        };
        let Some(addr) = self.dca1000 else {
            return Ok(None);
        };
        Ok(Some(metamoran::live::Link {
            addr,
            from: self.from,
            control: self.control,
            start: seconds(self.start_s, "--start-s")?,
            idle: seconds(self.idle_s, "--idle-s")?,
            on_listen: |at| eprintln!("listening for the DCA1000's samples on {at}"),
        }))
    }

    /// With `--dca1000`: the stream recorded for the bundle in `dir` (see
    /// [`metamoran::live::Link::capture_for`]), its report on stderr. Keep it while the bundle
    /// is read.
    ///
    /// # Errors
    /// As that, or bad seconds.
    pub fn capture_for(
        &self,
        dir: &Path,
    ) -> Result<Option<metamoran::live::Live>, metamoran::Error> {
        let Some(link) = self.link()? else {
            return Ok(None);
        };
        let live = link.capture_for(dir)?;
        eprint!(
            "{}",
            super::record::Report::new(live.file.path(), &live.recording)
        );
        Ok(Some(live))
    }
}

/// A password for `flag`'s user: the first line of `file`, else environment variable `env`;
/// never the command line.
///
/// # Errors
/// An unreadable file, or neither given.
pub fn password(file: Option<&Path>, env: &str, flag: &str) -> Result<String, metamoran::Error> {
    match (file, std::env::var(env)) {
        (Some(file), _) => Ok(std::fs::read_to_string(file)
            .map_err(|e| format!("{flag} password file {}: {e}", file.display()))?
            .lines()
            .next()
            .unwrap_or_default()
            .to_owned()),
        (None, Ok(p)) => Ok(p),
        (None, Err(_)) => Err(format!(
            "{flag}: give the password in {env} or a password file (never on the command line)"
        )
        .into()),
    }
}

/// The NATS server of the site stream and how to log in.
#[derive(clap::Args, Debug, Clone)]
pub struct NatsServerArgs {
    /// NATS server (nats://HOST:PORT, or tls://HOST:PORT with --nats-ca): tracks and health on
    /// core NATS, alerts into the site's JetStream stream, under metamoran.<site>.<sensor>.
    #[arg(long, value_name = "URL")]
    pub nats: Option<String>,
    /// NATS user; the password comes from METAMORAN_NATS_PASSWORD or --nats-password-file.
    #[arg(long, requires = "nats")]
    pub nats_user: Option<String>,
    /// File holding the NATS password (its first line).
    #[arg(long, value_name = "FILE", requires = "nats_user")]
    pub nats_password_file: Option<PathBuf>,
    /// PEM file of the CA that signs the NATS server's certificate (TLS required then).
    #[arg(long, value_name = "PEM", requires = "nats")]
    pub nats_ca: Option<PathBuf>,
}

impl NatsServerArgs {
    /// The server for sensor `sensor` of site `site`, if `--nats` was given.
    ///
    /// # Errors
    /// A malformed URL, site or sensor, or a missing password.
    pub fn config(
        &self,
        site: &str,
        sensor: &str,
    ) -> Result<Option<metamoran_operator::nats::NatsConfig>, metamoran::Error> {
        let Some(url) = &self.nats else {
            return Ok(None);
        };
        let mut config = metamoran_operator::nats::NatsConfig::new(url, site, sensor)?;
        config.ca.clone_from(&self.nats_ca);
        if let Some(user) = &self.nats_user {
            let password = password(
                self.nats_password_file.as_deref(),
                "METAMORAN_NATS_PASSWORD",
                "--nats-user",
            )?;
            config.login = Some(metamoran_operator::mqtt::MqttLogin::new(user, password));
        }
        Ok(Some(config))
    }
}

/// The NATS server and the site name.
#[derive(clap::Args, Debug, Clone)]
pub struct NatsArgs {
    /// The server and login.
    #[command(flatten)]
    pub server: NatsServerArgs,
    /// Site name (the subject level under metamoran.).
    #[arg(long, default_value = "demo")]
    pub site: String,
}

impl NatsArgs {
    /// The server for sensor `sensor`, if `--nats` was given.
    ///
    /// # Errors
    /// As [`NatsServerArgs::config`].
    pub fn config(
        &self,
        sensor: &str,
    ) -> Result<Option<metamoran_operator::nats::NatsConfig>, metamoran::Error> {
        self.server.config(&self.site, sensor)
    }
}
