//! Scene arrays larger than one storage binding, split into pages. The BVH nodes, the
//! gathered triangles, the shading entries and the textures are each uploaded as consecutive
//! buffers of at most the device's largest binding; the first page keeps the array's own
//! binding ([`crate::bindings`]), the others are bound past the integrators' bindings, and the
//! kernels read a paged array through a generated accessor that picks the page. A scene whose
//! arrays each fit one binding compiles the program unchanged, so the limit on a scene is the
//! device's memory, not one binding. Where the pages would need more storage buffers than a
//! shader stage may bind (48 on lavapipe), each array's extra pages are bound as one binding
//! array instead ([`PageBinding::Arrays`]), on devices that have them.

use crate::bake::replace_reads;
use crate::bindings::{self, Binding};
use crate::{GpuContext, GpuError};

/// One of the scene arrays that may span several bindings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PagedArray {
    /// BVH nodes, in the scene's layout (binding 1).
    Nodes,
    /// Gathered BVH triangles and instance records (binding 2).
    Triangles,
    /// Per-triangle shading entries (binding 3).
    Shading,
    /// Texture headers and mip chains (binding 11).
    Textures,
}

impl PagedArray {
    /// Every paged array, in the order their extra bindings are numbered.
    pub const ALL: [PagedArray; 4] = [PagedArray::Nodes, PagedArray::Triangles, PagedArray::Shading, PagedArray::Textures];

    /// The binding of the array's first page, which the program declares.
    pub fn binding(self) -> Binding {
        match self {
            PagedArray::Nodes => bindings::BVH_NODES,
            PagedArray::Triangles => bindings::BVH_TRIANGLES,
            PagedArray::Shading => bindings::SHADING,
            PagedArray::Textures => bindings::TEXTURES,
        }
    }

    /// What the array is called in messages.
    pub fn label(self) -> &'static str {
        match self {
            PagedArray::Nodes => "BVH nodes",
            PagedArray::Triangles => "BVH triangles",
            PagedArray::Shading => "triangle shading",
            PagedArray::Textures => "textures",
        }
    }

    fn index(self) -> usize {
        PagedArray::ALL.iter().position(|&a| a == self).expect("listed")
    }
}

/// How large an array is, for planning its pages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Extent {
    /// Bytes of the whole array.
    pub bytes: u64,
    /// Bytes of one stored element: pages end between elements.
    pub element: u64,
    /// Bytes of one element of the WGSL array that reads it (a quantised wide node read with
    /// 64-bit loads is two `vec4<u64>`); divides `element`.
    pub read_stride: u64,
}

/// How one array is split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Split {
    /// Buffers the array is uploaded in (1: one binding, as the program declares it).
    pub pages: u32,
    /// Bytes of every page but the last (whole elements, at most the binding limit); 0 for an
    /// array in one page.
    pub page_bytes: u64,
    /// Bytes of one element of the WGSL array that reads it ([`Extent::read_stride`]); 0 for
    /// an array in one page.
    pub read_stride: u64,
}

impl Split {
    /// An array in one binding.
    pub const WHOLE: Split = Split { pages: 1, page_bytes: 0, read_stride: 0 };

    /// Elements of the WGSL array in every page but the last.
    pub fn page_elements(&self) -> u64 {
        self.page_bytes.checked_div(self.read_stride).unwrap_or(0)
    }
}

/// How the pages past each array's first are bound.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PageBinding {
    /// One storage binding per page: every device has them, but they count against the
    /// storage buffers a shader stage may bind.
    #[default]
    Buffers,
    /// One binding array per paged array (`binding_array<...>`, indexed per lane), for scenes
    /// whose pages pass the storage buffers per stage; needs the device's binding arrays of
    /// storage buffers ([`binding_arrays_supported`]).
    Arrays,
}

/// The device features binding arrays of storage buffers indexed per lane need; requested
/// where the adapter has them ([`crate::GpuContext::device_descriptor`]).
pub const BINDING_ARRAY_FEATURES: wgpu::Features = wgpu::Features::BUFFER_BINDING_ARRAY
    .union(wgpu::Features::STORAGE_RESOURCE_BINDING_ARRAY)
    .union(wgpu::Features::SAMPLED_TEXTURE_AND_STORAGE_BUFFER_ARRAY_NON_UNIFORM_INDEXING);

/// Whether `ctx`'s device can bind pages as binding arrays ([`PageBinding::Arrays`]).
pub fn binding_arrays_supported(ctx: &GpuContext) -> bool {
    ctx.device.features().contains(BINDING_ARRAY_FEATURES) && ctx.limits.max_binding_array_elements_per_shader_stage > 0
}

/// The pages of a scene's four paged arrays; part of the [`crate::kernel::Kernel`], since
/// a paged array's reads are compiled for its page size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Paging {
    splits: [Split; 4],
    binding: PageBinding,
}

impl Default for Paging {
    fn default() -> Paging {
        Paging { splits: [Split::WHOLE; 4], binding: PageBinding::Buffers }
    }
}

/// The binding of the first extra page; the integrators' own bindings (and the ray bench's)
/// lie below it.
pub const FIRST_PAGE_BINDING: u32 = bindings::INTEGRATOR_BINDINGS.len() as u32;

impl Paging {
    /// Pages of at most `limit` bytes for arrays of `extents` (in [`PagedArray::ALL`]'s
    /// order). Fails when one element is larger than `limit`, or an array has more elements
    /// than a 32-bit index reaches.
    pub fn plan(extents: [Extent; 4], limit: u64) -> Result<Paging, GpuError> {
        let mut splits = [Split::WHOLE; 4];
        for (split, (array, extent)) in splits.iter_mut().zip(PagedArray::ALL.iter().zip(extents)) {
            if extent.bytes <= limit {
                continue;
            }
            let page_bytes = limit / extent.element * extent.element;
            if page_bytes == 0 {
                let what = format!("one of the {} of {} bytes", array.label(), extent.element);
                return Err(GpuError::Limit { what, need: extent.element, limit });
            }
            if extent.bytes / extent.read_stride > u64::from(u32::MAX) {
                return Err(GpuError::Scene(format!(
                    "the {} are {} elements; the kernels index at most {} of them",
                    array.label(),
                    extent.bytes / extent.read_stride,
                    u32::MAX
                )));
            }
            let pages = u32::try_from(extent.bytes.div_ceil(page_bytes)).expect("fewer pages than elements");
            *split = Split { pages, page_bytes, read_stride: extent.read_stride };
        }
        Ok(Paging { splits, binding: PageBinding::Buffers })
    }

    /// This paging with its extra pages bound as `binding`.
    pub fn bound_as(self, binding: PageBinding) -> Paging {
        Paging { binding, ..self }
    }

    /// How the extra pages are bound.
    pub fn binding(&self) -> PageBinding {
        self.binding
    }

    /// The paging a pipeline binding `base_storage` storage buffers besides the pages can use
    /// on `ctx`'s device: pages as storage buffers where they fit the storage buffers per
    /// shader stage, else as binding arrays where the device has them and their elements
    /// fit. Fails naming the pages and the limits when neither fits.
    pub fn fit(self, ctx: &GpuContext, base_storage: u32) -> Result<Paging, GpuError> {
        let extra = self.extra_pages().len() as u32;
        let allowed = ctx.limits.max_storage_buffers_per_shader_stage;
        if base_storage + extra <= allowed {
            return Ok(self.bound_as(PageBinding::Buffers));
        }
        let elements = ctx.limits.max_binding_array_elements_per_shader_stage;
        let arrays_supported = binding_arrays_supported(ctx);
        if arrays_supported && extra <= elements {
            return Ok(self.bound_as(PageBinding::Arrays));
        }
        let pages: Vec<String> = self.array_bindings().iter().map(|&(a, _)| format!("{} in {} pages", a.label(), self.split(a).pages)).collect();
        let arrays = if arrays_supported {
            format!("binding arrays of at most {elements} elements (max_binding_array_elements_per_shader_stage)")
        } else {
            "no binding arrays of storage buffers".to_string()
        };
        Err(GpuError::Scene(format!(
            "the scene needs {} storage bindings ({}, of at most {} each), but this device allows {allowed} per shader stage \
             (max_storage_buffers_per_shader_stage) and has {arrays}: render a smaller scene, or use a device with larger or more bindings",
            base_storage + extra,
            pages.join(", "),
            crate::memory::byte_size(ctx.max_storage_binding()),
        )))
    }

    /// How `array` is split.
    pub fn split(&self, array: PagedArray) -> Split {
        self.splits[array.index()]
    }

    /// Whether one of `arrays` spans more than one binding.
    pub fn is_paged(&self, arrays: &[PagedArray]) -> bool {
        arrays.iter().any(|&a| self.split(a).pages > 1)
    }

    /// The pages past each array's first: (array, page, binding), bindings numbered from
    /// [`FIRST_PAGE_BINDING`] in [`PagedArray::ALL`]'s order.
    pub fn extra_pages(&self) -> Vec<(PagedArray, u32, u32)> {
        let pages = PagedArray::ALL.iter().flat_map(|&array| (1..self.split(array).pages).map(move |page| (array, page)));
        pages.zip(FIRST_PAGE_BINDING..).map(|((array, page), binding)| (array, page, binding)).collect()
    }

    /// The binding of each paged array's binding array ([`PageBinding::Arrays`]): numbered
    /// from [`FIRST_PAGE_BINDING`] in [`PagedArray::ALL`]'s order, for the arrays with pages
    /// past their first.
    fn array_bindings(&self) -> Vec<(PagedArray, u32)> {
        let paged = PagedArray::ALL.into_iter().filter(|&a| self.split(a).pages > 1);
        paged.zip(FIRST_PAGE_BINDING..).collect()
    }

    /// The layout entries of the extra pages of `arrays` (read-only storage, compute): one
    /// per page, or one binding array per array.
    pub fn layout_entries(&self, arrays: &[PagedArray]) -> Vec<wgpu::BindGroupLayoutEntry> {
        let storage = wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only: true }, has_dynamic_offset: false, min_binding_size: None };
        let entry = |binding, count| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty: storage, count };
        match self.binding {
            PageBinding::Buffers => {
                self.extra_pages().into_iter().filter(|(array, _, _)| arrays.contains(array)).map(|(_, _, binding)| entry(binding, None)).collect()
            }
            PageBinding::Arrays => self
                .array_bindings()
                .into_iter()
                .filter(|(array, _)| arrays.contains(array))
                .map(|(array, binding)| entry(binding, std::num::NonZeroU32::new(self.split(array).pages - 1)))
                .collect(),
        }
    }

    /// The buffer lists the binding arrays of `arrays` bind ([`PageBinding::Arrays`]; none
    /// otherwise), kept by the caller for [`Paging::bind_entries`].
    pub fn buffer_arrays<'a>(&self, arrays: &[(PagedArray, &'a [wgpu::Buffer])]) -> Vec<(u32, Vec<wgpu::BufferBinding<'a>>)> {
        if self.binding == PageBinding::Buffers {
            return Vec::new();
        }
        let pages = |array| arrays.iter().find(|(a, _)| *a == array).map(|(_, pages)| *pages);
        self.array_bindings()
            .into_iter()
            .filter_map(|(array, binding)| Some((binding, pages(array)?[1..].iter().map(|b| b.as_entire_buffer_binding()).collect())))
            .collect()
    }

    /// The bind group entries of every page of the arrays given with their buffers (one
    /// buffer per page, as [`crate::GpuScene`] holds them); `buffer_arrays` is
    /// [`Paging::buffer_arrays`] of the same arrays.
    pub fn bind_entries<'a>(
        &self,
        arrays: &[(PagedArray, &'a [wgpu::Buffer])],
        buffer_arrays: &'a [(u32, Vec<wgpu::BufferBinding<'a>>)],
    ) -> Vec<wgpu::BindGroupEntry<'a>> {
        let mut entries: Vec<_> =
            arrays.iter().map(|(array, pages)| wgpu::BindGroupEntry { binding: array.binding().index, resource: pages[0].as_entire_binding() }).collect();
        match self.binding {
            PageBinding::Buffers => {
                for (array, page, binding) in self.extra_pages() {
                    if let Some((_, pages)) = arrays.iter().find(|(a, _)| *a == array) {
                        entries.push(wgpu::BindGroupEntry { binding, resource: pages[page as usize].as_entire_binding() });
                    }
                }
            }
            PageBinding::Arrays => {
                entries.extend(
                    buffer_arrays
                        .iter()
                        .map(|(binding, buffers)| wgpu::BindGroupEntry { binding: *binding, resource: wgpu::BindingResource::BufferArray(buffers) }),
                );
            }
        }
        entries
    }

    /// `program` reading each paged array it declares through an accessor that picks the
    /// page: its reads `name[i]` become `name_paged(i)`, and the extra pages' declarations
    /// and the accessors are appended (after `enable wgpu_binding_array;` at the top for
    /// [`PageBinding::Arrays`]). Unchanged when nothing is paged.
    pub fn apply(&self, program: &str) -> String {
        let mut source = program.to_string();
        let mut generated = String::new();
        for (array, split) in PagedArray::ALL.iter().zip(self.splits) {
            let name = array.binding().name;
            if split.pages < 2 {
                continue;
            }
            let Some(element) = declared_element(program, name) else { continue };
            source = replace_reads(&source, name, &format!("{name}_paged"));
            generated.push_str(&match self.binding {
                PageBinding::Buffers => accessor(*array, name, &element, split, &self.extra_pages()),
                PageBinding::Arrays => {
                    let binding = self.array_bindings().into_iter().find(|(a, _)| a == array).map(|(_, b)| b).expect("a paged array");
                    array_accessor(name, &element, split, binding)
                }
            });
        }
        if generated.is_empty() {
            return source;
        }
        if self.binding == PageBinding::Arrays {
            source.insert_str(0, "enable wgpu_binding_array;\n");
        }
        source.push_str("// ---- generated by crates/caustic-gpu/src/pages.rs: arrays past one binding ----\n");
        source.push_str(&generated);
        source
    }
}

/// The element type `T` of `program`'s `var<storage, read> name: array<T>;`, if declared.
fn declared_element(program: &str, name: &str) -> Option<String> {
    let declaration = format!("var<storage, read> {name}: array<");
    let rest = &program[program.find(&declaration)? + declaration.len()..];
    Some(rest[..rest.find(">;")?].to_string())
}

/// WGSL declaring `array`'s extra pages and `name_paged(i)`, which reads element `i` of the
/// whole array from its page.
fn accessor(array: PagedArray, name: &str, element: &str, split: Split, extra: &[(PagedArray, u32, u32)]) -> String {
    let per_page = split.page_elements();
    let mut text = String::new();
    let mut body = format!("    if i < {per_page}u {{ return {name}[i]; }}\n");
    for &(_, page, binding) in extra.iter().filter(|(a, _, _)| *a == array) {
        let first = per_page * u64::from(page);
        text.push_str(&format!("@group(0) @binding({binding}) var<storage, read> {name}_page{page}: array<{element}>;\n"));
        body.push_str(&if page + 1 < split.pages {
            format!("    if i < {}u {{ return {name}_page{page}[i - {first}u]; }}\n", first + per_page)
        } else {
            format!("    return {name}_page{page}[i - {first}u];\n")
        });
    }
    text.push_str(&format!("fn {name}_paged(i: u32) -> {element} {{\n{body}}}\n"));
    text
}

/// WGSL declaring the binding array of `name`'s extra pages (at `binding`, each page a
/// struct around its elements, as binding arrays of storage buffers need) and `name_paged(i)`,
/// which reads element `i` of the whole array from its page: the first page's binding, or the
/// binding array indexed by the page (per lane: the index need not be uniform).
fn array_accessor(name: &str, element: &str, split: Split, binding: u32) -> String {
    let (per_page, pages) = (split.page_elements(), split.pages - 1);
    format!(
        "struct {name}_page {{ items: array<{element}> }}\n\
         @group(0) @binding({binding}) var<storage, read> {name}_pages: binding_array<{name}_page, {pages}>;\n\
         fn {name}_paged(i: u32) -> {element} {{\n\
         \x20   if i < {per_page}u {{ return {name}[i]; }}\n\
         \x20   let page = i / {per_page}u - 1u;\n\
         \x20   return {name}_pages[page].items[i - (page + 1u) * {per_page}u];\n\
         }}\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn extent(bytes: u64, element: u64) -> Extent {
        Extent { bytes, element, read_stride: element }
    }

    #[test]
    fn arrays_past_the_limit_are_split_into_pages_of_whole_elements() {
        let extents = [Extent { bytes: 64 * 1000, element: 64, read_stride: 32 }, extent(48 * 100, 48), extent(80 * 3000, 80), extent(4 * 10, 4)];
        let paging = Paging::plan(extents, 99_999).expect("plan");
        let nodes = paging.split(PagedArray::Nodes);
        assert_eq!(nodes, Split::WHOLE, "64,000 bytes fit one binding");
        let shading = paging.split(PagedArray::Shading);
        assert_eq!((shading.pages, shading.page_bytes, shading.page_elements()), (3, 99_920, 1249));
        assert_eq!(paging.extra_pages(), vec![(PagedArray::Shading, 1, FIRST_PAGE_BINDING), (PagedArray::Shading, 2, FIRST_PAGE_BINDING + 1)]);
        let paging =
            Paging::plan([Extent { bytes: 64 * 1000, element: 64, read_stride: 32 }, extent(48, 48), extent(80, 80), extent(4, 4)], 1000).expect("plan");
        let nodes = paging.split(PagedArray::Nodes);
        assert_eq!((nodes.pages, nodes.page_bytes, nodes.page_elements()), (67, 960, 30), "pages end between nodes, read as two words each");
        assert!(matches!(Paging::plan([extent(200, 100), extent(0, 48), extent(0, 80), extent(0, 4)], 64), Err(GpuError::Limit { .. })));
    }

    #[test]
    fn the_accessor_reads_each_element_from_its_page() {
        let paging = Paging::plan([extent(64, 64), extent(48 * 10, 48), extent(80, 80), extent(4, 4)], 48 * 4).expect("plan");
        let program = "@group(0) @binding(2) var<storage, read> bvh_triangles: array<BvhTriangle>;\nfn f(i: u32) -> u32 { return bvh_triangles[bvh_triangles[i].id].id; }\n";
        let paged = paging.apply(program);
        println!("{paged}");
        assert!(paged.contains("return bvh_triangles_paged(bvh_triangles_paged(i).id).id;"), "reads rewritten, nested ones too");
        assert!(paged.contains(&format!("@group(0) @binding({}) var<storage, read> bvh_triangles_page2: array<BvhTriangle>;", FIRST_PAGE_BINDING + 1)));
        assert!(paged.contains(
            "    if i < 4u { return bvh_triangles[i]; }\n    if i < 8u { return bvh_triangles_page1[i - 4u]; }\n    return bvh_triangles_page2[i - 8u];\n"
        ));
        assert_eq!(Paging::default().apply(program), program, "nothing paged: the program as it is");
        let arrays = paging.bound_as(PageBinding::Arrays).apply(program);
        println!("{arrays}");
        assert!(arrays.starts_with("enable wgpu_binding_array;\n"));
        assert!(
            arrays.contains(&format!("@group(0) @binding({FIRST_PAGE_BINDING}) var<storage, read> bvh_triangles_pages: binding_array<bvh_triangles_page, 2>;"))
        );
        assert!(arrays.contains("    let page = i / 4u - 1u;\n    return bvh_triangles_pages[page].items[i - (page + 1u) * 4u];\n"));
    }
}
