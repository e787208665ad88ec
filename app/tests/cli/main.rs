//! The `motion-shadows` command line, one test binary for the layer: the binary as users
//! script it (`scripted`), what it answers to a user's mistakes (`user_errors`) and to hostile
//! inputs (`hostile_inputs`), the deferred frame's and `compare`'s options (`frame_options`),
//! the engine bench (`bench_engine`), `animate`'s timing options through the parser
//! (`animate_options`), and what takes a moving light or camera and what refuses it
//! (`moving_light`, `moving_camera`). Every run of the binary has the validation layer on.

mod animate_options;
mod bench_engine;
mod common;
mod frame_options;
mod hostile_inputs;
mod moving_camera;
mod moving_light;
mod scripted;
mod user_errors;
