//! What both ABI files need from C: strings and arrays from raw pointers, and the guard
//! every entry point runs the instance core in (state check, panic caught and reported).

use std::ffi::{c_char, c_int, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::instance::{Call, Instance, Status};

/// Reads a C string; `None` for null or invalid UTF-8.
///
/// # Safety
/// `p` is null or points to a NUL-terminated string.
pub unsafe fn text(p: *const c_char) -> Option<String> {
    if p.is_null() {
        return None;
    }
    unsafe { CStr::from_ptr(p) }
        .to_str()
        .ok()
        .map(str::to_string)
}

/// A slice from a C array; `None` if the pointer is null while `n > 0`.
///
/// # Safety
/// A non-null `p` points to `n` valid values.
pub unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    match (p.is_null(), n) {
        (_, 0) => Some(&[]),
        (true, _) => None,
        (false, _) => Some(unsafe { std::slice::from_raw_parts(p, n) }),
    }
}

/// A mutable slice from a C array; `None` if the pointer is null while `n > 0`.
///
/// # Safety
/// A non-null `p` points to `n` valid, writable values.
pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    match (p.is_null(), n) {
        (_, 0) => Some(&mut []),
        (true, _) => None,
        (false, _) => Some(unsafe { std::slice::from_raw_parts_mut(p, n) }),
    }
}

/// Runs `f` on the instance behind `c` (after checking `call` against the state machine)
/// inside a panic guard: a panic becomes an Error status, a logged message and an instance
/// that only allows get, reset and free.
pub fn guard(
    c: *mut c_void,
    call: Option<(Call, &str)>,
    f: impl FnOnce(&mut Instance) -> Status,
) -> c_int {
    if c.is_null() {
        return Status::Error as c_int;
    }
    // SAFETY: a non-null instance pointer comes from the instantiate function of the same
    // ABI and has not been freed (the importer's obligation under the standard).
    let instance = unsafe { &mut *(c as *mut Instance) };
    let result = catch_unwind(AssertUnwindSafe(|| {
        if let Some((call, name)) = call {
            if let Err(s) = instance.check(call, name) {
                return s;
            }
        }
        f(instance)
    }));
    match result {
        Ok(s) => s as c_int,
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            let _ = catch_unwind(AssertUnwindSafe(|| {
                instance.poison();
                instance.error(
                    Status::Error,
                    &format!("internal error (panic caught at the FMI boundary): {what}"),
                )
            }));
            Status::Error as c_int
        }
    }
}
