//! QEMU mps2-an500 support: CMSDK timer 0, semihosting exit, panic and fault handlers.
//!
//! Under `qemu-system-arm -icount shift=0` each guest instruction advances virtual time by
//! 1 ns, and timer 0 counts down at 25 MHz, so one tick is 40 instructions: differences of
//! [`Timer0::now`] give deterministic instruction counts.

use core::ptr::{read_volatile, write_volatile};
// Links cortex-m, which provides the single-core critical section semihosting needs.
use cortex_m as _;
use cortex_m_semihosting::debug;

/// Base address of the CMSDK APB timer 0.
const TIMER0: usize = 0x4000_0000;
/// Guest instructions per timer tick with `-icount shift=0` (1 ns per instruction, 25 MHz timer).
pub const INSTRUCTIONS_PER_TICK: u32 = 40;

/// CMSDK timer 0 running freely from `u32::MAX` down.
pub struct Timer0(());

impl Timer0 {
    /// Starts the timer (reload and value at `u32::MAX`, enabled, no interrupt).
    pub fn start() -> Self {
        // SAFETY: documented CMSDK timer registers (CTRL 0x0, VALUE 0x4, RELOAD 0x8) on this board.
        unsafe {
            write_volatile((TIMER0 + 0x8) as *mut u32, u32::MAX);
            write_volatile((TIMER0 + 0x4) as *mut u32, u32::MAX);
            write_volatile(TIMER0 as *mut u32, 1);
        }
        Self(())
    }

    /// The current count (decreasing).
    pub fn now(&self) -> u32 {
        // SAFETY: reading the VALUE register has no side effect.
        unsafe { read_volatile((TIMER0 + 0x4) as *const u32) }
    }

    /// Timer ticks spent in `f`.
    pub fn ticks(&self, f: impl FnOnce()) -> u32 {
        let start = self.now();
        f();
        start.wrapping_sub(self.now())
    }
}

/// Ends the QEMU run with a success or failure exit code.
pub fn exit(success: bool) -> ! {
    debug::exit(if success {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    #[allow(clippy::empty_loop)]
    loop {}
}

/// Logs where the panic happened (defmt, without `core::fmt`) and exits QEMU with failure.
#[cfg(not(feature = "no-panic-check"))]
#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    match info.location() {
        Some(at) => defmt::error!("panic at {=str}:{=u32}", at.file(), at.line()),
        None => defmt::error!("panic"),
    }
    exit(false)
}

/// With feature `no-panic-check` the panic handler calls a function that does not exist: the
/// release link then fails unless the optimizer removed every path to a panic.
#[cfg(feature = "no-panic-check")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    unsafe extern "C" {
        fn a_panic_path_is_linked_into_the_firmware() -> !;
    }
    // SAFETY: never runs: the symbol is undefined, so this only links if unreachable.
    unsafe { a_panic_path_is_linked_into_the_firmware() }
}

/// Defines a HardFault handler that reports the fault and exits QEMU with failure (a plain
/// `udf` loop would hang QEMU). Use once in each binary.
#[macro_export]
macro_rules! hard_fault_exits {
    () => {
        #[cortex_m_rt::exception]
        unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
            defmt::error!("HardFault at pc={=u32:#010x}", frame.pc());
            $crate::board::exit(false)
        }
    };
}

impl crate::clock::Monotonic for Timer0 {
    /// Microseconds from the 25 MHz count (wraps every 171 s of guest time; differences over
    /// shorter spans stay right).
    fn micros(&mut self) -> u32 {
        (u32::MAX - self.now()) / 25
    }
}

/// A capture file on the host, read through semihosting (QEMU `target=native`).
pub struct SemihostingFile {
    handle: usize,
}

impl SemihostingFile {
    /// Opens the file named by the `index`-th word of the semihosting command line
    /// (`-semihosting-config enable=on,target=native,arg=edge,arg=PATH`); `None` if there is
    /// no such argument or the host cannot open it.
    pub fn from_cmdline(index: usize) -> Option<Self> {
        let mut line = [0u8; 256];
        let block = [line.as_mut_ptr() as usize, line.len() - 1];
        // SAFETY: SYS_GET_CMDLINE writes at most `block[1]` bytes into `line`.
        let r =
            unsafe { cortex_m_semihosting::syscall(cortex_m_semihosting::nr::GET_CMDLINE, &block) };
        if r != 0 {
            return None;
        }
        let end = line.iter().position(|&b| b == 0).unwrap_or(line.len() - 1);
        let text = line.get(..end)?;
        let path = text
            .split(|&b| b == b' ')
            .filter(|w| !w.is_empty())
            .nth(index)?;
        Self::open(path)
    }

    /// Opens host file `path` for reading; `None` if the host cannot open it.
    pub fn open(path: &[u8]) -> Option<Self> {
        let mut name = [0u8; 256];
        name.get_mut(..path.len())?.copy_from_slice(path);
        // SYS_OPEN mode 1 = "rb"; the name is NUL-terminated and its length excludes the NUL.
        let args = [name.as_ptr() as usize, 1, path.len()];
        // SAFETY: the name buffer outlives the call.
        let handle =
            unsafe { cortex_m_semihosting::syscall(cortex_m_semihosting::nr::OPEN, &args) };
        (handle != usize::MAX).then_some(Self { handle })
    }
}

/// The emulated board's TRNG: mps2-an500 has none, so QEMU's host supplies the entropy
/// (`/dev/urandom` through semihosting). A real module implements the same traits over its RNG
/// peripheral (an STM32H7's RNG, for instance).
pub struct HostEntropy(SemihostingFile);

/// The host's entropy file could not be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EntropyError;

impl core::fmt::Display for EntropyError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("the entropy source could not be read")
    }
}

impl core::error::Error for EntropyError {}

impl HostEntropy {
    /// Opens `/dev/urandom` on the host; `None` if semihosting cannot.
    pub fn open() -> Option<Self> {
        SemihostingFile::open(b"/dev/urandom").map(Self)
    }
}

impl rand_core::TryRngCore for HostEntropy {
    type Error = EntropyError;

    fn try_next_u32(&mut self) -> Result<u32, EntropyError> {
        let mut b = [0u8; 4];
        self.try_fill_bytes(&mut b)?;
        Ok(u32::from_le_bytes(b))
    }

    fn try_next_u64(&mut self) -> Result<u64, EntropyError> {
        let mut b = [0u8; 8];
        self.try_fill_bytes(&mut b)?;
        Ok(u64::from_le_bytes(b))
    }

    fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), EntropyError> {
        crate::capture::CaptureSource::read_exact(&mut self.0, dest).map_err(|_| EntropyError)
    }
}

impl rand_core::TryCryptoRng for HostEntropy {}

impl crate::capture::CaptureSource for SemihostingFile {
    fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), crate::capture::SourceError> {
        let args = [self.handle, buf.as_mut_ptr() as usize, buf.len()];
        // SAFETY: SYS_READ writes at most `buf.len()` bytes into `buf`; returns the bytes not read.
        let left = unsafe { cortex_m_semihosting::syscall(cortex_m_semihosting::nr::READ, &args) };
        if left == 0 {
            Ok(())
        } else {
            Err(crate::capture::SourceError::Ended)
        }
    }
}

/// Stack high-water mark by painting: the free stack is filled with a pattern at boot, and the
/// deepest word no longer holding it shows how far the stack grew.
pub struct StackGauge {
    top: usize,
    bottom: usize,
}

const PAINT: u32 = 0xACE0_BA5E;

unsafe extern "C" {
    static _stack_start: u32;
    static _stack_end: u32;
}

impl StackGauge {
    /// Paints the stack below the current frame (call first thing in `main`).
    pub fn paint() -> Self {
        let top = core::ptr::addr_of!(_stack_start) as usize;
        let bottom = core::ptr::addr_of!(_stack_end) as usize;
        // Leave 256 bytes under the live stack pointer for this function's own frame.
        let sp = cortex_m::register::msp::read() as usize - 256;
        let mut at = bottom;
        while at < sp {
            // SAFETY: words between the end of .bss/.uninit and the stack pointer are unused.
            unsafe { write_volatile(at as *mut u32, PAINT) };
            at += 4;
        }
        Self { top, bottom }
    }

    /// Bytes of stack used at the deepest point so far.
    pub fn high_water(&self) -> usize {
        let mut at = self.bottom;
        // SAFETY: reading words of the stack region.
        while at < self.top && unsafe { read_volatile(at as *const u32) } == PAINT {
            at += 4;
        }
        self.top - at
    }

    /// [`Self::high_water`] of the stack painted at boot, as a plain function (for
    /// [`crate::module::Module::with_stack_gauge`]).
    pub fn stack_high_water() -> u32 {
        Self {
            top: core::ptr::addr_of!(_stack_start) as usize,
            bottom: core::ptr::addr_of!(_stack_end) as usize,
        }
        .high_water() as u32
    }
}
