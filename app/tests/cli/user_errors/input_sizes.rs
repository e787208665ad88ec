//! Runaway memory: scene files and OBJ models that would be read or built without bound.

use super::*;

// ---------------------------------------------------------------------------------------
// Runaway memory: sizes are checked before anything of that size is read or built.

#[test]
fn endless_scene_file_and_obj_are_refused_without_reading_them_whole() {
    let dir = temp_dir("endless");
    let r = run(&["render", "--scene-file", "/dev/zero", "--out", s(&dir)]);
    r.refused(&["/dev/zero", "MiB"]);

    let obj = r#"{ "name": "zero", "albedo": [0.5, 0.5, 0.5], "mesh": { "obj": "/dev/zero" } }"#;
    let scene = write_scene(
        &dir,
        "obj.json",
        &scene_json("obj", 0.1, "[0, 5, 0]", &[floor(4.0), obj.into()]),
    );
    render_file(&scene, &dir, &[]).refused(&["/dev/zero", "not a regular file", "\"zero\""]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn absurd_triangle_counts_are_refused_before_building() {
    let dir = temp_dir("counts");
    for cubes in ["5000000", "50000000"] {
        let r = run(&[
            "render",
            "--scene",
            "random-cubes",
            "--cubes",
            cubes,
            "--out",
            s(&dir),
        ]);
        r.refused(&["cube count", "33554432"]);
    }
    // A box of 1024 x 1024 quads a face would need a 1.2 GB vertex buffer.
    let fine_box = r#"{ "name": "fine", "albedo": [0.5, 0.5, 0.5], "closed": true,
        "mesh": { "box": { "size": [1, 1, 1], "subdivisions": 1024 } } }"#;
    let scene = write_scene(
        &dir,
        "fine.json",
        &scene_json("fine", 0.1, "[0, 5, 0]", &[floor(4.0), fine_box.into()]),
    );
    render_file(&scene, &dir, &[]).refused(&["\"fine\"", "subdivisions", "256"]);
    // 200 boxes at the limit: each fits, together they do not.
    let many: Vec<String> = (0..200)
        .map(|i| {
            format!(
                r#"{{ "name": "b{i}", "albedo": [0.5, 0.5, 0.5],
                    "mesh": {{ "box": {{ "size": [1, 1, 1], "subdivisions": 256 }} }} }}"#
            )
        })
        .collect();
    let scene = write_scene(
        &dir,
        "many.json",
        &scene_json("many", 0.1, "[0, 5, 0]", &many),
    );
    render_file(&scene, &dir, &[]).refused(&["157286400 triangles", "limit"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
