//! The firmware under QEMU (mps2-an500, Cortex-M7): it must boot, run the self-test, and
//! compute exactly the bits the host computes with the same `dsp` code.

use host_tools::qemu;
use metamoran_e2e::oracles_required;
use std::time::Duration;

fn qemu_available() -> bool {
    std::process::Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn firmware_self_test_matches_host_bit_for_bit() {
    if !qemu_available() {
        assert!(
            !oracles_required(),
            "qemu-system-arm is required (apt-get install -y qemu-system-arm)"
        );
        eprintln!("SKIPPED: qemu-system-arm not installed");
        return;
    }
    let elf = qemu::build("firmware").unwrap();
    let out = qemu::run(&elf, false, Duration::from_secs(60)).unwrap();
    let module: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("SELFTEST ") && !l.ends_with("done"))
        .collect();
    let mut host = Vec::new();
    firmware::selftest::run(|o| {
        host.push(format!(
            "SELFTEST {} exp={} hash={:08x}",
            o.name, o.exponent, o.hash
        ))
    });
    assert!(
        out.contains("SELFTEST done"),
        "self-test did not finish:\n{out}"
    );
    assert_eq!(module, host, "the module and the host disagree");
}
