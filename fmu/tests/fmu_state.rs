//! FMU states through the C ABI, FMI 2 and FMI 3, both models: a state taken mid-run and
//! set back into the same instance, set into another instance, and serialized then
//! deserialized into a fresh instance continues bit for bit as the uninterrupted run (a
//! fresh instance needs no initialization: the state carries the phase). Bytes of another
//! model, another build, another format version, damaged or not a state at all are refused
//! with a message saying which; 1,000 get/set/free cycles leave the memory the thread holds
//! exactly where it was.

// Unsafe code: these tests call the C ABI.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::ptr::null_mut;
use std::sync::Mutex;

mod common;
use common::{steps, Abi, Fmi2, Fmi3, Run, ABDOMEN, CUTBLOCK, ERROR, ERRORS, OK};

/// Counts the bytes each thread holds (allocated minus freed).
struct Counting;

thread_local! {
    static HELD: Cell<isize> = const { Cell::new(0) };
}

fn held(change: isize) {
    let _ = HELD.try_with(|h| h.set(h.get() + change));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        held(layout.size() as isize);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        held(-(layout.size() as isize));
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        held(new_size as isize - layout.size() as isize);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

const AT: usize = 3;
const END: usize = 7;

/// The three ways back: the same instance, another one, and bytes into a fresh one.
fn continues<A: Abi>(run: &Run) {
    let a = A::instantiate(run);
    A::initialize(a, run);
    steps::<A>(a, run, 0, AT);
    let mut state = null_mut();
    assert_eq!(A::get_state(a, &mut state), OK);
    let bytes = A::serialize(a, state);
    let expected = steps::<A>(a, run, AT, END);
    // Back in the same instance.
    assert_eq!(A::set_state(a, state), OK);
    assert_eq!(steps::<A>(a, run, AT, END), expected, "same instance");
    // In another instance, initialized or not.
    let b = A::instantiate(run);
    assert_eq!(A::set_state(b, state), OK);
    assert_eq!(steps::<A>(b, run, AT, END), expected, "another instance");
    // From the bytes, in a fresh instance.
    let c = A::instantiate(run);
    let mut read = null_mut();
    assert_eq!(A::deserialize(c, &bytes, &mut read), OK);
    assert_eq!(A::set_state(c, read), OK);
    assert_eq!(steps::<A>(c, run, AT, END), expected, "from bytes");
    // The state is the same written twice.
    assert_eq!(A::serialize(c, read), bytes);
    for (i, mut s) in [(a, state), (c, read)] {
        assert_eq!(A::free_state(i, &mut s), OK);
        assert!(s.is_null());
    }
    for i in [a, b, c] {
        A::free(i);
    }
}

#[test]
fn a_state_continues_bit_for_bit_in_fmi2() {
    continues::<Fmi2>(&CUTBLOCK);
    continues::<Fmi2>(&ABDOMEN);
}

#[test]
fn a_state_continues_bit_for_bit_in_fmi3() {
    continues::<Fmi3>(&CUTBLOCK);
    continues::<Fmi3>(&ABDOMEN);
}

/// The bytes of a state of `run`'s model after one step.
fn bytes_of<A: Abi>(run: &Run) -> Vec<u8> {
    let c = A::instantiate(run);
    A::initialize(c, run);
    steps::<A>(c, run, 0, 1);
    let mut s = null_mut();
    assert_eq!(A::get_state(c, &mut s), OK);
    let bytes = A::serialize(c, s);
    A::free_state(c, &mut s);
    A::free(c);
    bytes
}

/// `bytes` with the header field at `at` (after magic and version) replaced, checksum fixed.
fn with_crc(mut bytes: Vec<u8>) -> Vec<u8> {
    let n = bytes.len() - 4;
    let crc = crc32fast::hash(&bytes[..n]);
    bytes[n..].copy_from_slice(&crc.to_le_bytes());
    bytes
}

/// Deserializing `bytes` into a cut-block instance is refused; the message logged.
fn refused(bytes: &[u8]) -> String {
    let c = Fmi3::instantiate(&CUTBLOCK);
    ERRORS.lock().unwrap().clear();
    let mut s = null_mut();
    assert_eq!(Fmi3::deserialize(c, bytes, &mut s), ERROR);
    assert!(s.is_null());
    Fmi3::free(c);
    ERRORS.lock().unwrap().join("\n")
}

#[test]
fn foreign_and_damaged_bytes_are_refused_saying_why() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let own = bytes_of::<Fmi3>(&CUTBLOCK);
    let e = refused(&bytes_of::<Fmi3>(&ABDOMEN));
    assert!(
        e.contains("is of the `abdomen` model; this FMU is `cutblock`"),
        "{e}"
    );
    let e = refused(b"hello, this is no state");
    assert!(e.contains("not a serialized tissuefmu FMU state"), "{e}");
    let mut damaged = own.clone();
    let middle = damaged.len() / 2;
    damaged[middle] ^= 1;
    let e = refused(&damaged);
    assert!(e.contains("corrupted: its checksum does not match"), "{e}");
    let e = refused(&own[..own.len() - 9]);
    assert!(e.contains("corrupted") || e.contains("truncated"), "{e}");
    let mut version = own.clone();
    version[16] = 9;
    let e = refused(&with_crc(version));
    assert!(
        e.contains("format version 9; this build reads version 1"),
        "{e}"
    );
    // Another build: the same model's name, another token.
    let name = 1 + own[20] as usize;
    let mut build = own.clone();
    build[20 + name + 1] ^= 0x20;
    let e = refused(&with_crc(build));
    assert!(
        e.contains("comes from another build of the `cutblock` FMU"),
        "{e}"
    );
    // A state of the abdomen set in a cut-block instance of the same library.
    let a = Fmi3::instantiate(&ABDOMEN);
    let mut s = null_mut();
    assert_eq!(Fmi3::get_state(a, &mut s), OK);
    let c = Fmi3::instantiate(&CUTBLOCK);
    ERRORS.lock().unwrap().clear();
    assert_eq!(Fmi3::set_state(c, s), ERROR);
    let e = ERRORS.lock().unwrap().join("\n");
    assert!(
        e.contains("an FMU state of the `abdomen` model cannot be set in a `cutblock`"),
        "{e}"
    );
    Fmi3::free_state(a, &mut s);
    Fmi3::free(a);
    Fmi3::free(c);
}

/// Tests that read the shared error log take turns.
static SERIAL: Mutex<()> = Mutex::new(());

/// Getting, setting and freeing a state 1,000 times gives back every byte: the thread holds
/// as much after as before.
#[test]
fn a_thousand_get_set_free_cycles_leave_memory_flat() {
    let c = Fmi2::instantiate(&CUTBLOCK);
    Fmi2::initialize(c, &CUTBLOCK);
    steps::<Fmi2>(c, &CUTBLOCK, 0, 2);
    let cycle = || {
        let mut s = null_mut();
        assert_eq!(Fmi2::get_state(c, &mut s), OK);
        assert_eq!(Fmi2::set_state(c, s), OK);
        assert_eq!(Fmi2::free_state(c, &mut s), OK);
    };
    for _ in 0..10 {
        cycle();
    }
    let before = HELD.with(Cell::get);
    for _ in 0..1000 {
        cycle();
    }
    assert_eq!(HELD.with(Cell::get) - before, 0);
    Fmi2::free(c);
}
