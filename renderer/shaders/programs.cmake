# Every GL program SplatRenderer builds: its shader files and every set of #defines it may compile them
# with. The one list of define sets: the build validates each (validate_shaders.cmake) and the renderer
# refuses a set that is not here (programSource() in src/gl/shader_sources.h), so the two cannot drift.
#
# shader_program(<name> FILES <stage files> AXES <axis>...): a program's define sets are every way of
# taking one alternative from each axis. An axis lists alternatives separated by "|"; an alternative
# lists defines separated by ",", each NAME or NAME=VALUE; an empty alternative defines nothing, so
# "|HEATMAP" reads "without or with HEATMAP". Values must match the renderer's constants (kOpaqueTilePx,
# kSplatTilePx, recordVec4s(), entryTexels(), runLanes).

# The three shading choices, one axis: SplatSettings::Shading picks one.
# The sizes of tiled splatting's records and list entries follow it (recordVec4s(), entryTexels()).
string(CONCAT shading_axis "RECORD_VEC4S=3u,ENTRY_TEXELS=2u"
                           "|SPLAT_SHADING,RECORD_VEC4S=3u,ENTRY_TEXELS=3u"
                           "|FRAGMENT_SHADING,RECORD_VEC4S=4u,ENTRY_TEXELS=3u")

# Rasterised splats (SplatRenderer::Gl::splatProgram): the variant bits of SplatVariant.
shader_program(splat FILES splat.vert splat.frag
  AXES OPAQUE_TILE=8 "|COUNTERS" "|SURFACE" "|SPLAT_SHADING|FRAGMENT_SHADING" "|HEATMAP" "|ADAPTIVE"
       "|OCCLUSION" "|GRADIENT_OPACITY|TF_2D")

# Tiled splatting's four passes (Gl::tileProgram). RUN_LANES: 8 on llvmpipe, 64 elsewhere.
set(tile_header OPAQUE_TILE=8 SPLAT_TILE=8 BUSY_ROW=4096u)
shader_program(tile_record FILES tile_record.comp
  AXES ${tile_header} "|COUNTERS" "|SURFACE" "${shading_axis}" "|ADAPTIVE" "|OCCLUSION"
       "RUN_LANES=8|RUN_LANES=64" "|GRADIENT_OPACITY|TF_2D")
shader_program(tile_offsets FILES tile_offsets.comp AXES ${tile_header} RECORD_VEC4S=3u ENTRY_TEXELS=2u)
shader_program(tile_bases FILES tile_bases.comp AXES ${tile_header} RECORD_VEC4S=3u ENTRY_TEXELS=2u)
shader_program(tile_scatter FILES tile_scatter.comp AXES ${tile_header} "${shading_axis}" "|OCCLUSION")
shader_program(tile_composite FILES tile_composite.comp
  AXES ${tile_header} "${shading_axis}" "|HEATMAP" "|OCCLUSION" "|XRAY" "|COLUMN_RECURRENCE")
# The composite shaped for a GPU (a pixel per invocation; DriverProfile::compositePerPixel).
shader_program(tile_composite_pixels FILES tile_composite_pixels.comp
  AXES ${tile_header} "${shading_axis}" "|HEATMAP" "|OCCLUSION" "|XRAY")

# Full-screen passes and small compute passes, built once in SplatRenderer's constructor.
shader_program(sheet_composite FILES fullscreen.vert sheet_composite.frag AXES "|HEATMAP")
shader_program(opaque_mask FILES fullscreen.vert opaque_mask.frag)
shader_program(xray_resolve FILES fullscreen.vert xray_resolve.frag)
shader_program(display FILES fullscreen.vert display.frag)
shader_program(bucket_commands FILES bucket_commands.comp)
shader_program(patch_modes FILES patch_modes.comp)
shader_program(opaque_tiles FILES opaque_tiles.comp AXES OPAQUE_TILE=8)
shader_program(loop_limit FILES loop_limit.comp)
# The near layer (near_layer_pass.cpp); MAX_NEAR_KERNELS: kMaxNearKernels (renderer/oracle/near_layer.h).
shader_program(near_kernels FILES near_kernels.comp AXES MAX_NEAR_KERNELS=1024u)
shader_program(near_layer FILES fullscreen.vert near_layer.frag AXES MAX_NEAR_KERNELS=1024u)
# Image-aligned slabs' per-pixel pass (image_slabs_gl.cpp).
shader_program(slab_composite FILES slab_composite.comp)
