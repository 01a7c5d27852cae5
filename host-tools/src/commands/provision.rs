//! `metamoran provision`: a new device key for one module, and the module image built with it.

use super::args::Locations;
use std::fmt;
use std::path::PathBuf;

/// Provision a module: write a fresh device key (OS random generator, mode 0600) for the host,
/// and with --image build the module's `edge` firmware with that key inside.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  metamoran provision --device gate-east --out keys\n  metamoran provision --device gate-east --out keys --image\n  metamoran process site --edge qemu --link-key-file keys/gate-east.key"
)]
pub struct Args {
    /// The module's name: the files are DEVICE.key (and DEVICE.elf).
    #[arg(long)]
    device: String,
    /// Folder for the key file (and the image); created if missing.
    #[arg(long, default_value = "keys")]
    out: PathBuf,
    /// Also build the `edge` firmware with the key built in, as OUT/DEVICE.elf.
    #[arg(long)]
    image: bool,
}

/// What was provisioned.
#[derive(Debug, serde::Serialize)]
pub struct Provisioned {
    /// The host's key file.
    pub key_file: PathBuf,
    /// The module image with the key inside, if built.
    pub image: Option<PathBuf>,
}

impl fmt::Display for Provisioned {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "device key: {} (keep it secret; mode 0600)",
            self.key_file.display()
        )?;
        match &self.image {
            Some(elf) => writeln!(f, "module image with the key inside: {}", elf.display())?,
            None => writeln!(
                f,
                "build the module with METAMORAN_LINK_KEY_FILE={} (or rerun with --image)",
                self.key_file.display()
            )?,
        }
        writeln!(
            f,
            "host: --link-key-file {} (or METAMORAN_LINK_KEY_FILE)",
            self.key_file.display()
        )
    }
}

/// Runs `metamoran provision`.
///
/// # Errors
/// A bad device name, an existing key file (never overwritten), or a failed build.
pub fn run(args: &Args, locations: &Locations) -> super::Result {
    let name_ok = !args.device.is_empty()
        && args
            .device
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if !name_ok {
        return Err(format!(
            "--device \"{}\": use letters, digits, '-' and '_' (it names files)",
            args.device
        )
        .into());
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("--out {}: cannot create it ({e})", args.out.display()))?;
    let key_file = args.out.join(format!("{}.key", args.device));
    metamoran_edge::keys::write_key_file(&key_file)?;
    let image = if args.image {
        let elf = metamoran_edge::qemu::build(&locations.firmware()?, "edge", Some(&key_file))?;
        let target = args.out.join(format!("{}.elf", args.device));
        std::fs::copy(&elf, &target)
            .map_err(|e| format!("{}: cannot write ({e})", target.display()))?;
        Some(target)
    } else {
        None
    };
    print!("{}", Provisioned { key_file, image });
    Ok(())
}
