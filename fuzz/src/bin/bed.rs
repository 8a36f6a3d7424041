//! AFL++ entry point of the `bed` target ([`packbed_fuzz::bed`]).

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let _ = packbed_fuzz::bed(data);
    });
}
