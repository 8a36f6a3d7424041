//! AFL++ entry point of the `psd_table` target ([`packbed_fuzz::psd_table`]).

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let _ = packbed_fuzz::psd_table(data);
    });
}
