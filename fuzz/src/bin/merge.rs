//! AFL++ entry point of the `merge` target ([`packbed_fuzz::merge`]).

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let _ = packbed_fuzz::merge(data);
    });
}
