//! AFL++ entry point of the `config` target ([`packbed_fuzz::config`]).

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let _ = packbed_fuzz::config(data);
    });
}
