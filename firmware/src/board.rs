//! QEMU mps2-an500 support: CMSDK timer 0, semihosting exit, panic and fault handlers.
//!
//! Under `qemu-system-arm -icount shift=0` each guest instruction advances virtual time by
//! 1 ns, and timer 0 counts down at 25 MHz, so one tick is 40 instructions: differences of
//! [`Timer0::now`] give deterministic instruction counts.

use core::ptr::{read_volatile, write_volatile};
// Links cortex-m, which provides the single-core critical section semihosting needs.
use cortex_m as _;
use cortex_m_semihosting::{debug, hprintln};

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

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    hprintln!("PANIC: {}", info);
    exit(false)
}

/// Defines a HardFault handler that reports the fault and exits QEMU with failure (a plain
/// `udf` loop would hang QEMU). Use once in each binary.
#[macro_export]
macro_rules! hard_fault_exits {
    () => {
        #[cortex_m_rt::exception]
        unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
            cortex_m_semihosting::hprintln!("HARDFAULT at pc={:#010x}", frame.pc());
            $crate::board::exit(false)
        }
    };
}
