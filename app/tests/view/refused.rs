//! What `view` cannot do is refused by name.

use crate::support::*;

#[test]
fn view_refuses_what_it_cannot_do_by_name() {
    // Without a display: it says so before opening anything.
    refused(&["--frames", "1"], None, "DISPLAY");
    // Scripted-only options without --frames.
    refused(&["--screenshot", "x.png"], Some(":0"), "--frames");
    refused(&["--resize", "64x64"], Some(":0"), "--frames");
    refused(
        &["--tsm-maps", "0", "--frames", "1"],
        Some(":0"),
        "--tsm-maps",
    );
    refused(
        &["--camera-time", "2", "--frames", "1"],
        Some(":0"),
        "--camera-time",
    );
    refused(
        &["--resize", "0x64", "--frames", "1"],
        Some(":0"),
        "--resize",
    );
    refused(&["--spp", "0", "--frames", "1"], Some(":0"), "--spp");
    refused(
        &[
            "--method",
            "temporal-exact",
            "--shadow-filter",
            "bilinear",
            "--frames",
            "1",
        ],
        Some(":0"),
        "--shadow-filter bilinear",
    );
    refused(
        &["--frame", "forward", "--method", "tsm", "--frames", "1"],
        Some(":0"),
        "--frame forward",
    );
    refused(
        &["--split", "tsm", "--method", "tsm", "--frames", "1"],
        Some(":0"),
        "--split tsm-8",
    );
    refused(
        &["--split", "plain", "--frame", "forward", "--frames", "1"],
        Some(":0"),
        "--split plain",
    );
}
