//! AFL++ entry point of the `compare` target ([`packbed_fuzz::compare`]).

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let _ = packbed_fuzz::compare(data);
    });
}
