//! AFL++ entry point of the `resume` target ([`packbed_fuzz::resume`]).

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let _ = packbed_fuzz::resume(data);
    });
}
