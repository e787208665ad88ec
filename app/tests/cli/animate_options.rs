//! `animate`'s timing options through the real command-line parser, on generated values:
//! plain, extreme, negative, non-finite and malformed `--fps`, `--start` and `--frames`. Every
//! set the parser accepts must give what a frame needs without a panic or a silent change:
//! a GIF delay that holds 1 / fps (at most 655.35 s, in hundredths), and frame times that are
//! finite and strictly increasing (in f64, as `animate` computes them: `start + i / fps`).
//! Every set it refuses must be refused by a message naming the option. Seeded, a fixed
//! number of cases, no device.

use clap::Parser;
use motion_shadows_app::cli::args::{Cli, Command, MAX_GIF_DELAY_S};

use motion_shadows_test_support::rng::Rng;

const NUMBERS: &[&str] = &[
    "0",
    "1",
    "24",
    "100",
    "100.0001",
    "101",
    "0.001",
    "0.0015",
    "0.001526",
    "0.00153",
    "1e-20",
    "1e-45",
    "-1",
    "-24",
    "1e9",
    "1e8",
    "-1e9",
    "1.0000001e9",
    "1e10",
    "3.4e38",
    "1e39",
    "inf",
    "-inf",
    "NaN",
    "nan",
    "",
    " ",
    "abc",
    "1,5",
    "0x10",
    "2.5",
    "1e-3",
    "12345678901234567890",
    "600",
    "601",
    "-0",
    "+3",
];

fn value(rng: &mut Rng) -> String {
    if rng.below(3) == 0 {
        // A random decimal in a wide range of magnitudes.
        let mantissa = (rng.next() % 10_000) as f64 / 1000.0;
        let exponent = rng.below(25) as i32 - 12;
        let sign = if rng.below(4) == 0 { "-" } else { "" };
        format!("{sign}{mantissa}e{exponent}")
    } else {
        rng.pick(NUMBERS).to_owned()
    }
}

#[test]
fn animate_timing_options_are_checked_where_they_are_parsed() {
    let mut rng = Rng(0x616e_696d);
    let (mut accepted, mut refused) = (0, 0);
    for case in 0..20_000 {
        let mut args = vec!["motion-shadows".to_owned(), "animate".to_owned()];
        let mut named = Vec::new();
        for option in ["--fps", "--start", "--frames"] {
            if rng.below(3) != 0 {
                args.push(option.to_owned());
                args.push(value(&mut rng));
                named.push(option);
            }
        }
        match Cli::try_parse_from(&args) {
            Err(e) => {
                refused += 1;
                let message = e.to_string();
                assert!(
                    named.iter().any(|o| message.contains(o)),
                    "case {case} {args:?}: the refusal names no option: {message}"
                );
            }
            Ok(cli) => {
                accepted += 1;
                let Some(Command::Animate(a)) = cli.command else {
                    panic!("case {case}: not animate");
                };
                let delay = 1.0 / f64::from(a.fps);
                assert!(
                    a.fps.is_finite() && delay > 0.0 && delay <= MAX_GIF_DELAY_S + 1e-9,
                    "case {case} {args:?}: fps {} needs a {delay} s delay",
                    a.fps
                );
                let start = a.start.unwrap_or(0.0);
                let times: Vec<f64> = (0..a.frames)
                    .map(|i| start + f64::from(i) / f64::from(a.fps))
                    .collect();
                assert!(
                    times.iter().all(|t| t.is_finite()) && times.windows(2).all(|w| w[1] > w[0]),
                    "case {case} {args:?}: frame times {:?}..",
                    &times[..times.len().min(3)]
                );
            }
        }
    }
    println!("animate options: {accepted} accepted, {refused} refused");
    assert!(accepted > 1000 && refused > 1000, "{accepted} / {refused}");
}
