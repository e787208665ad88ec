//! `motion-shadows view` in a real window: a virtual X server (Xvfb, started here; the test
//! fails without it, or without a Vulkan device that presents to it), scripted runs of a few
//! frames, the validation layer and synchronization validation on. The presented frame, read
//! back from the swapchain image, must be the offline renderer's deferred frame of the same
//! camera, time and method (`render --frame deferred`), also after a resize, and the frames
//! after the first must allocate nothing (the exact lookup's too); the split view's halves
//! must be each method's frame.

mod exact_room;
mod keys;
mod moving;
mod presents;
mod refused;
mod split;
mod support;
