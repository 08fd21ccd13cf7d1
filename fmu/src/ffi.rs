//! What both ABI files share: C strings and arrays from raw pointers; instantiation and
//! freeing; the guard every entry point runs the instance core in (state check, panic caught
//! and reported, queued messages handed to the importer's logger once the instance is
//! released); and the calls whose marshalling is the same in FMI 2 and FMI 3 (debug
//! logging, real and string get/set, value types the models do not have). `fmi2.rs` and
//! `fmi3.rs` only convert their arguments into calls of these.

// Unsafe code: the C side of the FMI ABI: strings, arrays and instance handles from raw pointers.
#![allow(unsafe_code)]

use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;

use crate::exports::Version;
use crate::instance::{Instance, Log};
use crate::machine::{Call, Status};
use crate::state::FmuState;

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

/// A logger over an importer's callback: `send(status, category, message)` receives C
/// strings (NUL characters in the message replaced by spaces).
pub fn logger(send: impl Fn(Status, &CStr, &CStr) + Send + Sync + 'static) -> Log {
    Arc::new(move |status, category, message| {
        let category = CString::new(category).unwrap_or_default();
        let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
        send(status, &category, &message);
    })
}

/// A logger that drops everything (the importer gave no callback).
pub fn silent() -> Log {
    Arc::new(|_, _, _| {})
}

/// Creates an instance from C arguments and returns its handle, or null with the reason
/// logged: `refusal` (an argument the FMU cannot honour), a missing or foreign token, a bad
/// resource location. Never unwinds into the importer.
///
/// # Safety
/// The string pointers are null or NUL-terminated strings.
pub unsafe fn instantiate(
    version: Version,
    name: *const c_char,
    token: *const c_char,
    location: *const c_char,
    log: Log,
    logging_on: bool,
    refusal: Option<&str>,
) -> *mut c_void {
    let result = catch_unwind(AssertUnwindSafe(|| {
        if let Some(why) = refusal {
            log(Status::Error, "logStatusError", why);
            return std::ptr::null_mut();
        }
        let name = unsafe { text(name) }.unwrap_or_else(|| "tissuefmu".into());
        let token = unsafe { text(token) };
        let location = unsafe { text(location) };
        Instance::into_handle(Instance::create(
            version,
            token.as_deref(),
            &name,
            location.as_deref(),
            log,
            logging_on,
        ))
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// Frees an instance handle (null is ignored).
///
/// # Safety
/// `c` is null or a handle from [`instantiate`], not used afterwards.
pub unsafe fn free(c: *mut c_void) {
    if !c.is_null() {
        let _ = catch_unwind(|| drop(unsafe { Box::from_raw(c as *mut Instance) }));
    }
}

/// Runs `f` on the instance behind `c` (after checking `call` against the state machine)
/// inside a panic guard: a panic becomes an Error status, a logged message and an instance
/// that only allows get, reset and free. The messages the call queued go to the importer's
/// logger after the instance is released, so a logger that calls back into the FMU gets an
/// instance of its own, not an alias of this one.
pub fn guard(
    c: *mut c_void,
    call: Option<(Call, &str)>,
    f: impl FnOnce(&mut Instance) -> Status,
) -> c_int {
    if c.is_null() {
        return Status::Error as c_int;
    }
    let (status, log, messages) = {
        // SAFETY: a non-null instance pointer comes from `instantiate` and has not been freed
        // (the importer's obligation under the standard). This borrow ends with the block.
        let instance = unsafe { &mut *(c as *mut Instance) };
        let result = catch_unwind(AssertUnwindSafe(|| {
            if let Some((call, name)) = call {
                if let Err(s) = instance.check(call, name) {
                    return s;
                }
            }
            f(instance)
        }));
        let status = result.unwrap_or_else(|panic| {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            instance.poison();
            instance.error(
                Status::Error,
                &format!("internal error (panic caught at the FMI boundary): {what}"),
            )
        });
        (status, instance.logger(), instance.take_messages())
    };
    for (s, category, message) in messages {
        let _ = catch_unwind(AssertUnwindSafe(|| log(s, category, &message)));
    }
    status as c_int
}

/// `SetDebugLogging`.
///
/// # Safety
/// `categories` is null or points to `n` C strings.
pub unsafe fn set_debug_logging(
    c: *mut c_void,
    function: &str,
    on: bool,
    categories: *const *const c_char,
    n: usize,
) -> c_int {
    guard(c, Some((Call::SetDebugLogging, function)), |i| {
        let Some(cats) = (unsafe { slice(categories, n) }) else {
            return i.error(Status::Error, &format!("{function}: categories is null"));
        };
        let cats: Vec<String> = cats
            .iter()
            .map(|&p| unsafe { text(p) }.unwrap_or_default())
            .collect();
        i.set_debug_logging(on, &cats)
    })
}

/// `GetReal` / `GetFloat64`.
///
/// # Safety
/// `vr` points to `nvr` references and `values` to `n` writable values (or are null when
/// their count is 0).
pub unsafe fn get_reals(
    c: *mut c_void,
    function: &str,
    vr: *const u32,
    nvr: usize,
    values: *mut f64,
    n: usize,
) -> c_int {
    guard(c, Some((Call::Get, function)), |i| {
        match unsafe { (slice(vr, nvr), slice_mut(values, n)) } {
            (Some(vr), Some(values)) => i.get_reals(vr, values),
            _ => i.error(Status::Error, &format!("{function}: null array")),
        }
    })
}

/// `SetReal` / `SetFloat64`.
///
/// # Safety
/// `vr` points to `nvr` references and `values` to `n` values (or are null when their count
/// is 0).
pub unsafe fn set_reals(
    c: *mut c_void,
    function: &str,
    vr: *const u32,
    nvr: usize,
    values: *const f64,
    n: usize,
) -> c_int {
    guard(c, Some((Call::Set, function)), |i| {
        match unsafe { (slice(vr, nvr), slice(values, n)) } {
            (Some(vr), Some(values)) => i.set_reals(vr, values),
            _ => i.error(Status::Error, &format!("{function}: null array")),
        }
    })
}

/// `GetString`: the returned pointers stay valid until the next call on the instance.
///
/// # Safety
/// `vr` points to `nvr` references and `values` to `n` writable pointers.
pub unsafe fn get_strings(
    c: *mut c_void,
    function: &str,
    vr: *const u32,
    nvr: usize,
    values: *mut *const c_char,
    n: usize,
) -> c_int {
    guard(c, Some((Call::Get, function)), |i| {
        let (Some(vr), Some(values)) = (unsafe { slice(vr, nvr) }, unsafe { slice_mut(values, n) })
        else {
            return i.error(Status::Error, &format!("{function}: null array"));
        };
        if vr.len() != values.len() {
            return i.error(
                Status::Error,
                &format!("{function}: one value per reference expected"),
            );
        }
        match i.get_strings(vr) {
            Ok(strings) => {
                for (v, s) in values.iter_mut().zip(strings) {
                    *v = s.as_ptr();
                }
                Status::Ok
            }
            Err(s) => s,
        }
    })
}

/// `SetString`.
///
/// # Safety
/// `vr` points to `nvr` references and `values` to `n` C strings.
pub unsafe fn set_strings(
    c: *mut c_void,
    function: &str,
    vr: *const u32,
    nvr: usize,
    values: *const *const c_char,
    n: usize,
) -> c_int {
    guard(c, Some((Call::Set, function)), |i| {
        let (Some(vr), Some(values)) = (unsafe { slice(vr, nvr) }, unsafe { slice(values, n) })
        else {
            return i.error(Status::Error, &format!("{function}: null array"));
        };
        let Some(values) = values
            .iter()
            .map(|&p| unsafe { text(p) })
            .collect::<Option<Vec<_>>>()
        else {
            return i.error(
                Status::Error,
                &format!("{function}: null or non-UTF-8 string"),
            );
        };
        if vr.len() != values.len() {
            return i.error(
                Status::Error,
                &format!("{function}: one value per reference expected"),
            );
        }
        i.set_strings(vr, &values)
    })
}

/// Get or set of a value type the models do not have: no references is fine, any reference
/// is unknown.
pub fn no_variables(c: *mut c_void, function: &str, call: Call, nvr: usize) -> c_int {
    guard(c, Some((call, function)), |i| {
        if nvr == 0 {
            Status::Ok
        } else {
            i.error(
                Status::Error,
                &format!("{function}: the model has no variables of this type"),
            )
        }
    })
}

/// A function of a capability the model description declares absent.
pub fn unsupported(c: *mut c_void, function: &str) -> c_int {
    guard(c, None, |i| {
        i.error(
            Status::Error,
            &format!("{function} is not supported (see the model description's capability flags)"),
        )
    })
}

/// `…GetFMUState`: the instance's state into `*slot` — a new one if `*slot` is null, else
/// over the state `*slot` holds (FMI 2 allows the importer to pass one back for reuse).
///
/// # Safety
/// `slot` is null or points to null or to a state from this library, not freed.
pub unsafe fn get_state(c: *mut c_void, function: &str, slot: *mut *mut c_void) -> c_int {
    guard(c, Some((Call::State, function)), |i| {
        let Some(slot) = (unsafe { slot.as_mut() }) else {
            return i.error(
                Status::Error,
                &format!("{function}: the state pointer is null"),
            );
        };
        unsafe { store(slot, i.get_state()) };
        Status::Ok
    })
}

/// Puts `state` into `*slot`: a new allocation if it is null, else over the state it holds.
///
/// # Safety
/// `*slot` is null or a state from this library, not freed.
unsafe fn store(slot: &mut *mut c_void, state: FmuState) {
    match unsafe { (*slot as *mut FmuState).as_mut() } {
        Some(old) => *old = state,
        None => *slot = Box::into_raw(Box::new(state)).cast(),
    }
}

/// `…SetFMUState`.
///
/// # Safety
/// `state` is null or a state from this library, not freed.
pub unsafe fn set_state(c: *mut c_void, function: &str, state: *mut c_void) -> c_int {
    guard(c, Some((Call::State, function)), |i| {
        match unsafe { (state as *const FmuState).as_ref() } {
            Some(state) => i.set_state(state),
            None => i.error(Status::Error, &format!("{function}: the state is null")),
        }
    })
}

/// `…FreeFMUState`: frees `*slot` (null is fine) and sets it to null.
///
/// # Safety
/// `slot` is null or points to null or to a state from this library, not freed.
pub unsafe fn free_state(c: *mut c_void, function: &str, slot: *mut *mut c_void) -> c_int {
    guard(c, Some((Call::State, function)), |_| {
        if let Some(slot) = unsafe { slot.as_mut() } {
            if !slot.is_null() {
                drop(unsafe { Box::from_raw(*slot as *mut FmuState) });
                *slot = std::ptr::null_mut();
            }
        }
        Status::Ok
    })
}

/// `…SerializedFMUStateSize`.
///
/// # Safety
/// `state` is null or a state from this library; `size` is null or writable.
pub unsafe fn state_size(
    c: *mut c_void,
    function: &str,
    state: *mut c_void,
    size: *mut usize,
) -> c_int {
    guard(c, Some((Call::State, function)), |i| {
        let (Some(state), Some(size)) = (unsafe { (state as *const FmuState).as_ref() }, unsafe {
            size.as_mut()
        }) else {
            return i.error(Status::Error, &format!("{function}: a null argument"));
        };
        match i.serialize(state) {
            Ok(bytes) => {
                *size = bytes.len();
                Status::Ok
            }
            Err(status) => status,
        }
    })
}

/// `…SerializeFMUState`: the serialized state into `buffer` of exactly its size.
///
/// # Safety
/// `state` is null or a state from this library; `buffer` is null or holds `size` bytes.
pub unsafe fn serialize_state(
    c: *mut c_void,
    function: &str,
    state: *mut c_void,
    buffer: *mut u8,
    size: usize,
) -> c_int {
    guard(c, Some((Call::State, function)), |i| {
        let (Some(state), Some(buffer)) =
            (unsafe { (state as *const FmuState).as_ref() }, unsafe {
                slice_mut(buffer, size)
            })
        else {
            return i.error(Status::Error, &format!("{function}: a null argument"));
        };
        match i.serialize(state) {
            Ok(bytes) if bytes.len() == size => {
                buffer.copy_from_slice(bytes);
                Status::Ok
            }
            Ok(bytes) => {
                let message = format!(
                    "{function}: the buffer holds {size} bytes, the state needs {}",
                    bytes.len()
                );
                i.error(Status::Error, &message)
            }
            Err(status) => status,
        }
    })
}

/// `…DeserializeFMUState`: the state in `size` bytes into `*slot` (new if it is null, else
/// over the state it holds).
///
/// # Safety
/// `buffer` is null or holds `size` bytes; `slot` is null or points to null or to a state
/// from this library, not freed.
pub unsafe fn deserialize_state(
    c: *mut c_void,
    function: &str,
    buffer: *const u8,
    size: usize,
    slot: *mut *mut c_void,
) -> c_int {
    guard(c, Some((Call::State, function)), |i| {
        let (Some(bytes), Some(slot)) = (unsafe { slice(buffer, size) }, unsafe { slot.as_mut() })
        else {
            return i.error(Status::Error, &format!("{function}: a null argument"));
        };
        match i.deserialize(bytes) {
            Ok(state) => {
                unsafe { store(slot, state) };
                Status::Ok
            }
            Err(status) => status,
        }
    })
}

#[cfg(test)]
mod tests {
    use std::sync::{Arc, Mutex};

    use super::*;
    use crate::exports::{Version, EXPORTS};
    use crate::machine::Phase;

    /// A panic inside an entry point's work is an Error status at the boundary, logged with
    /// its message; the instance then refuses steps but still answers get, and frees.
    #[test]
    fn a_panic_inside_an_entry_point_is_an_error_status_and_poisons_the_instance() {
        let logged = Arc::new(Mutex::new(Vec::<(Status, String)>::new()));
        let sink = Arc::clone(&logged);
        let log: Log = Arc::new(move |s, _, m| sink.lock().unwrap().push((s, m.to_string())));
        let token = EXPORTS[1].token();
        let c = Instance::into_handle(Instance::create(
            Version::Fmi3,
            Some(&token),
            "guarded",
            None,
            log,
            false,
        ));
        assert!(!c.is_null());

        let status = guard(c, Some((Call::Set, "fmi3SetFloat64")), |_| {
            panic!("an index out of range deep in a scene")
        });
        assert_eq!(status, Status::Error as c_int);
        let (s, message) = logged.lock().unwrap().last().cloned().unwrap();
        assert_eq!(s, Status::Error);
        assert!(
            message.contains("panic caught at the FMI boundary")
                && message.contains("an index out of range deep in a scene"),
            "{message}"
        );

        let phase = |c| {
            let mut phase = None;
            guard(c, None, |i| {
                phase = Some(i.phase());
                Status::Ok
            });
            phase
        };
        assert_eq!(phase(c), Some(Phase::Error));
        let refused = guard(c, Some((Call::DoStep, "fmi3DoStep")), |_| Status::Ok);
        assert_eq!(refused, Status::Error as c_int);
        let read = guard(c, Some((Call::Get, "fmi3GetFloat64")), |_| Status::Ok);
        assert_eq!(read, Status::Ok as c_int);
        unsafe { free(c) };
    }
}
