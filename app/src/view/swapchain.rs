//! The window's swapchain: made for the surface's current size, made again after a resize or
//! when the surface says it is out of date. Its images are copy destinations (the frame is
//! blitted in) and copy sources (a screenshot reads back exactly what is presented).

use super::device::ViewDevice;
use anyhow::{Context as _, bail};
use ash::vk;

/// 8-bit formats the shading writes sRGB-encoded bytes for: presented as they are, so that a
/// screenshot's bytes are the bytes shown.
const FORMATS: [vk::Format; 2] = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM];

pub struct Swapchain {
    loader: ash::khr::swapchain::Device,
    pub handle: vk::SwapchainKHR,
    pub images: Vec<vk::Image>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    /// One per image: signalled by the frame that drew into it, waited for by its present
    /// (per image, not per frame slot: a present may still wait on it when the slot comes
    /// round again).
    pub rendered: Vec<vk::Semaphore>,
    device: ash::Device,
}

/// What acquiring an image found.
pub enum Acquired {
    /// An image to draw into; true: the swapchain no longer matches the surface exactly
    /// (suboptimal): it still presents, and is made again after.
    Image(u32, bool),
    /// The surface changed (resized, lost): make the swapchain again.
    OutOfDate,
}

/// The way the window system composites the images' alpha (one the surface supports, as
/// `vkCreateSwapchainKHR` requires); opaque where it can, else any other: the shading writes
/// alpha 1, so each shows the same pixels.
fn composite_alpha(
    supported: vk::CompositeAlphaFlagsKHR,
) -> anyhow::Result<vk::CompositeAlphaFlagsKHR> {
    use vk::CompositeAlphaFlagsKHR as A;
    [A::OPAQUE, A::INHERIT, A::PRE_MULTIPLIED, A::POST_MULTIPLIED]
        .into_iter()
        .find(|&mode| supported.contains(mode))
        .ok_or_else(|| {
            anyhow::anyhow!("the surface supports no way to composite the images ({supported:?})")
        })
}

/// The swapchain images' size for a window of `wanted` pixels: the surface's own extent,
/// or, where it lets the swapchain choose (`u32::MAX`), `wanted` within the surface's range;
/// None where that has no area (a minimized window): Vulkan allows no swapchain of it.
fn image_extent(caps: &vk::SurfaceCapabilitiesKHR, wanted: (u32, u32)) -> Option<vk::Extent2D> {
    let extent = if caps.current_extent.width != u32::MAX {
        caps.current_extent
    } else {
        vk::Extent2D {
            width: wanted
                .0
                .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
            height: wanted
                .1
                .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
        }
    };
    (extent.width > 0 && extent.height > 0).then_some(extent)
}

impl Swapchain {
    /// A swapchain of `wanted` pixels (the window's size; the surface's own extent where it
    /// has one), replacing `old` (which the caller destroys after); None, `old` left as it
    /// is, where the surface has no area (a minimized window).
    pub fn new(
        gpu: &ViewDevice,
        wanted: (u32, u32),
        old: vk::SwapchainKHR,
    ) -> anyhow::Result<Option<Self>> {
        let base = &gpu.base;
        let (physical, surface) = (gpu.physical, base.surface);
        // SAFETY: `physical` and `surface` belong to the instance `surface_loader` was made
        // from, and the surface is alive: `gpu.base` owns it and destroys it only after the
        // device, whose swapchains go first (the frame loop's field order).
        let caps = unsafe {
            base.surface_loader
                .get_physical_device_surface_capabilities(physical, surface)
        }
        .context("the surface's capabilities (was the window closed?)")?;
        // SAFETY: as above.
        let formats = unsafe {
            base.surface_loader
                .get_physical_device_surface_formats(physical, surface)
        }
        .context("the surface's formats")?;
        let Some(format) = FORMATS.iter().find_map(|&f| {
            formats
                .iter()
                .find(|s| s.format == f && s.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
                .copied()
        }) else {
            bail!("the surface offers none of {FORMATS:?} (sRGB non-linear): cannot present");
        };
        let usage = vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::TRANSFER_SRC;
        if !caps.supported_usage_flags.contains(usage) {
            bail!(
                "the surface's images cannot be copy destinations and sources ({:?})",
                caps.supported_usage_flags
            );
        }
        let Some(extent) = image_extent(&caps, wanted) else {
            return Ok(None);
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(composite_alpha(caps.supported_composite_alpha)?)
            // Always there; the frame rate is the renderer's, far below a display's on a CPU.
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(old);
        let loader = ash::khr::swapchain::Device::new(&base.instance, &gpu.device);
        // SAFETY: `loader` is of `gpu`'s device, made with the swapchain extension; `info`'s
        // surface is alive (above) and presentable from the device's queue family
        // (`pick_device`); its format, colour space, usage, count, transform, composite alpha
        // and present mode are among those the surface reported (FIFO always is), its extent
        // the surface's own or the caller's non-zero size clamped to the surface's range;
        // `old` is null or this surface's current swapchain, not yet destroyed (the caller's
        // contract).
        let handle =
            unsafe { loader.create_swapchain(&info, None) }.context("vkCreateSwapchainKHR")?;
        let mut this = Self {
            loader,
            handle,
            images: Vec::new(),
            format: format.format,
            extent,
            rendered: Vec::new(),
            device: gpu.device.clone(),
        };
        // SAFETY: `handle` was just made by this loader's device.
        this.images = unsafe { this.loader.get_swapchain_images(handle) }
            .context("vkGetSwapchainImagesKHR")?;
        for _ in 0..this.images.len() {
            // SAFETY: `this.device` is alive; on error `this` is dropped, destroying the
            // semaphores made so far and the swapchain.
            let semaphore = unsafe {
                this.device
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
            }
            .context("vkCreateSemaphore")?;
            this.rendered.push(semaphore);
        }
        Ok(Some(this))
    }

    pub fn size(&self) -> (u32, u32) {
        (self.extent.width, self.extent.height)
    }

    /// The next image to draw into, made available when `ready` is signalled.
    pub fn acquire(&self, ready: vk::Semaphore) -> anyhow::Result<Acquired> {
        // SAFETY: the swapchain is alive (`self`) and not retired: a new one replaces it only
        // in `make_swapchain`, which drops this one; `ready` is the slot's acquire semaphore,
        // unsignalled with no pending signal (the slot's last frame, which waited on it,
        // completed: its fence was waited for before this call).
        match unsafe {
            self.loader
                .acquire_next_image(self.handle, u64::MAX, ready, vk::Fence::null())
        } {
            Ok((index, suboptimal)) => Ok(Acquired::Image(index, suboptimal)),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(vk::Result::ERROR_SURFACE_LOST_KHR) => {
                bail!("the window's surface was lost (the window system closed it)")
            }
            Err(e) => Err(e).context("vkAcquireNextImageKHR"),
        }
    }

    /// Presents `index` once its frame signalled `rendered[index]`; false where the surface
    /// is out of date or the swapchain suboptimal (it must be made again).
    pub fn present(&self, queue: vk::Queue, index: u32) -> anyhow::Result<bool> {
        let swapchains = [self.handle];
        let indices = [index];
        let waits = [self.rendered[index as usize]];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: `queue` is the device's, of the family that presents to the surface;
        // `index` was acquired from this swapchain and the frame just submitted, which
        // signals `rendered[index]`, left the image in PRESENT_SRC_KHR; `info` borrows arrays
        // that live until the call returns.
        match unsafe { self.loader.queue_present(queue, &info) } {
            Ok(suboptimal) => Ok(!suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(vk::Result::ERROR_SURFACE_LOST_KHR) => {
                bail!("the window's surface was lost (the window system closed it)")
            }
            Err(e) => Err(e).context("vkQueuePresentKHR"),
        }
    }
}

impl Drop for Swapchain {
    /// The caller waited for the device (no present or frame uses the images).
    fn drop(&mut self) {
        // SAFETY: the semaphores and the swapchain are this device's, destroyed once; the
        // caller waited for the device, so no submission or present still uses them.
        unsafe {
            for &s in &self.rendered {
                self.device.destroy_semaphore(s, None);
            }
            self.loader.destroy_swapchain(self.handle, None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The swapchain asks only for a way of compositing alpha the surface offers (a surface
    /// need not offer opaque), opaque first, and refuses a surface that offers none.
    /// A minimized window's surface has no area (its extent 0x0, or a range whose largest
    /// is 0): no swapchain is made for it (Vulkan forbids a zero extent), the frame is
    /// skipped; otherwise the surface's own extent, or the window's size within its range.
    #[test]
    fn a_surface_without_area_gets_no_swapchain_extent() {
        let extent = |width, height| vk::Extent2D { width, height };
        let caps = |current, min, max| vk::SurfaceCapabilitiesKHR {
            current_extent: current,
            min_image_extent: min,
            max_image_extent: max,
            ..Default::default()
        };
        let any = extent(u32::MAX, u32::MAX);
        let cases = [
            // X11 and most: the surface says its size.
            (
                caps(extent(640, 360), extent(640, 360), extent(640, 360)),
                (640, 360),
                Some(extent(640, 360)),
            ),
            (
                caps(extent(0, 0), extent(0, 0), extent(0, 0)),
                (640, 360),
                None,
            ),
            (
                caps(extent(640, 0), extent(640, 0), extent(640, 0)),
                (640, 360),
                None,
            ),
            // Surfaces that let the swapchain choose.
            (
                caps(any, extent(1, 1), extent(4096, 4096)),
                (800, 5000),
                Some(extent(800, 4096)),
            ),
            (
                caps(any, extent(1, 1), extent(4096, 4096)),
                (0, 360),
                Some(extent(1, 360)),
            ),
            (caps(any, extent(0, 0), extent(0, 0)), (640, 360), None),
        ];
        for (caps, wanted, expected) in cases {
            assert_eq!(
                image_extent(&caps, wanted),
                expected,
                "{:?} in {:?}..{:?}, window {wanted:?}",
                caps.current_extent,
                caps.min_image_extent,
                caps.max_image_extent
            );
        }
    }

    #[test]
    fn composite_alpha_is_one_the_surface_supports() {
        use vk::CompositeAlphaFlagsKHR as A;
        let cases = [
            (A::OPAQUE | A::INHERIT, Some(A::OPAQUE)),
            (A::INHERIT, Some(A::INHERIT)),
            (
                A::PRE_MULTIPLIED | A::POST_MULTIPLIED,
                Some(A::PRE_MULTIPLIED),
            ),
            (A::POST_MULTIPLIED, Some(A::POST_MULTIPLIED)),
            (A::empty(), None),
        ];
        for (supported, expected) in cases {
            let chosen = composite_alpha(supported);
            match expected {
                Some(mode) => assert_eq!(chosen.ok(), Some(mode), "{supported:?}"),
                None => {
                    let message = chosen.err().map(|e| e.to_string()).unwrap_or_default();
                    assert!(message.contains("composite"), "{supported:?}: {message:?}");
                }
            }
        }
    }
}
