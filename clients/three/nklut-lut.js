// nklut-lut.js — nklut's Fresnel lookup textures in three.js (r187), as an ES module with no
// build step. It loads one atlas of `luts/` (any of the five encodings, PNG or EXR) with the
// loader settings that keep the sampling convention of docs/engine-integration.md, and makes
// a MeshPhysicalMaterial whose specular Fresnel is one row of it (through onBeforeCompile).
//
// The sampling convention (luts/manifest.json → sampling): row r of an atlas of `rows` rows
// holds F(cos θ) of one material, texel i of N at cos θ = (i + 0.5)/N; sampled with linear
// filtering and clamp-to-edge at u = cos θ and v at the row's centre, the texture unit
// returns the LUT model whose error the manifest states (rows[].error_vs_exact). What each
// encoding needs in three.js / WebGL2:
//
//   unorm8       PNG through TextureLoader, flipY = false (TextureLoader's default true would
//                put row r at rows − 1 − r), colorSpace = NoColorSpace (linear data: three
//                then uploads with UNPACK_COLORSPACE_CONVERSION_WEBGL = NONE, so the browser
//                applies neither the file's gAMA 1.0 nor a display profile): RGBA8.
//   unorm8-srgb  the same with colorSpace = SRGBColorSpace: SRGB8_ALPHA8, which the texture
//                unit decodes to linear before filtering (core WebGL2, filterable).
//   unorm16      browsers decode PNGs to 8 bits, so the file is decoded here (zlib through
//                DecompressionStream, PNG filters undone) and uploaded as UnsignedShortType:
//                RGBA16 needs EXT_texture_norm16 (it is filterable); without it, as
//                RGBA32F (needs OES_texture_float_linear to filter).
//   f16          EXR through EXRLoader as HalfFloatType: RGBA16F, core WebGL2 and filterable.
//   f32          EXR through EXRLoader as FloatType: RGBA32F, filterable only with
//                OES_texture_float_linear (checked: without it a linear sampler reads black).
//
// EXRLoader writes the file's scanlines bottom-up and sets flipY = false itself, so for the
// EXR atlases v = 1 − (row + 0.5)/rows; for the PNGs (flipY = false) v = (row + 0.5)/rows.
// `lut.v(row)` gives the right one. Mipmaps are off and both wrap modes clamp to edge.
//
// The material: where three's physical shading uses F_Schlick(F0, F90, ·) — the direct
// lights' microfacet term (at v·h), the diffuse layer's share of it, the environment's
// split-sum term (Fr·A + F90·B becomes F_LUT(n·v)·(A + B), so a smooth surface reflects
// F_LUT(n·v) of the environment) and the share a transmissive surface lets through
// (1 − F_LUT(n·v)) — it reads the LUT row instead; cos θ = clamp(dot(N, V), 0, 1) as the
// convention says. Everything else (roughness, transmission, attenuation, ior for the
// refracted direction) stays three's own. Defining NKLUT_OUTPUT_FRESNEL in material.defines
// makes the fragment shader write vec4(F_LUT(n·v), n·v) instead of the shaded colour: the
// Fresnel term alone, for checks (tests/clients/render_lut.html).
//
// Usage (an import map names 'three' and 'three/addons/', as three.js's own docs do):
//
//   import * as THREE from 'three';
//   import { loadNklutLut, nklutMaterial } from './nklut-lut.js';
//   const manifest = await (await fetch('luts/manifest.json')).json();
//   const lut = await loadNklutLut(renderer, manifest, { baseUrl: 'luts/', encoding: 'unorm8-srgb' });
//   mesh.material = nklutMaterial(lut, '3d/metals/gold', { roughness: 0.1 });

import * as THREE from 'three';
import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';

/** The encodings of a bake and how three.js loads each (see the header). */
export const ENCODINGS = Object.freeze({
  unorm8: { file: 'png', colorSpace: THREE.NoColorSpace },
  'unorm8-srgb': { file: 'png', colorSpace: THREE.SRGBColorSpace },
  unorm16: { file: 'png16' },
  f16: { file: 'exr', type: THREE.HalfFloatType },
  f32: { file: 'exr', type: THREE.FloatType },
});

/** GLSL of the lookup: the convention of docs/engine-integration.md, with the row's v given. */
export const NKLUT_GLSL = /* glsl */ `
uniform sampler2D nklutLut;
uniform float nklutV;
float nklutCos;
vec3 nklutFresnelNV;
// Texel i of N holds F at cos_theta = (i + 0.5)/N; linear filtering, clamp-to-edge, no mipmaps.
vec3 nklutFresnel( const in float cosTheta ) {
	return textureLod( nklutLut, vec2( clamp( cosTheta, 0.0, 1.0 ), nklutV ), 0.0 ).rgb;
}
`;

function fail(message) {
  throw new Error(`nklut-lut: ${message}`);
}

/** The texture set of `manifest` for a source and an encoding. */
export function textureSet(manifest, source, encoding) {
  const set = manifest.textures?.find((t) => t.source === source && t.encoding === encoding);
  if (!set) fail(`the manifest has no texture set ${source}/${encoding}`);
  if (!set.atlas) fail(`the texture set ${source}/${encoding} was baked without the atlas layout`);
  return set;
}

/**
 * Loads the atlas of one texture set. `options`: `baseUrl` (the folder holding manifest.json,
 * with a trailing '/'), `source` ('three-channel' by default), `encoding` ('unorm8-srgb' by
 * default), and `override` — for tests that show what a wrong setting does — `{ flipY }`
 * (the PNG loaders' flipY) and `{ rowOrder: 'file' }` (v as if EXRLoader kept the file's
 * order). Resolves to { texture, set, rows, encoding, v(row), row(page) }.
 */
export async function loadNklutLut(renderer, manifest, options = {}) {
  const { baseUrl = '', source = 'three-channel', encoding = 'unorm8-srgb', override = {} } = options;
  const how = ENCODINGS[encoding] ?? fail(`unknown encoding ${encoding}`);
  const set = textureSet(manifest, source, encoding);
  const url = baseUrl + set.atlas.file;
  const gl = renderer.getContext();
  if (!(typeof WebGL2RenderingContext !== 'undefined' && gl instanceof WebGL2RenderingContext)) fail('needs a WebGL2 renderer');
  let texture;
  let reversed = false;
  if (how.file === 'png') {
    texture = await new THREE.TextureLoader().loadAsync(url);
    texture.flipY = override.flipY ?? false;
    texture.colorSpace = how.colorSpace;
  } else if (how.file === 'png16') {
    const png = await decodePng16(await fetchBytes(url));
    const norm16 = renderer.extensions.has('EXT_texture_norm16');
    if (norm16) {
      // UnsignedShortType + RGBAFormat: three picks RGBA16_EXT when the extension is there.
      texture = new THREE.DataTexture(png.rgba, png.width, png.height, THREE.RGBAFormat, THREE.UnsignedShortType);
    } else {
      if (!renderer.extensions.has('OES_texture_float_linear')) fail('unorm16 needs EXT_texture_norm16 or OES_texture_float_linear');
      const float = Float32Array.from(png.rgba, (v) => v / 65535);
      texture = new THREE.DataTexture(float, png.width, png.height, THREE.RGBAFormat, THREE.FloatType);
    }
    // A DataTexture's rows are uploaded as given (first row first): no flip.
    texture.flipY = override.flipY ?? false;
    texture.colorSpace = THREE.NoColorSpace;
  } else {
    if (how.type === THREE.FloatType && !renderer.extensions.has('OES_texture_float_linear')) {
      fail('f32 needs OES_texture_float_linear to filter RGBA32F (use f16 or unorm16 instead)');
    }
    texture = await new EXRLoader().setDataType(how.type).loadAsync(url);
    texture.colorSpace = THREE.NoColorSpace;
    // EXRLoader reverses the scanlines (first file row at the bottom) and sets flipY = false.
    reversed = override.rowOrder !== 'file';
  }
  if (texture.image.width !== set.atlas.width || texture.image.height !== set.atlas.height) {
    fail(`${url} is ${texture.image.width}x${texture.image.height}, the manifest says ${set.atlas.width}x${set.atlas.height}`);
  }
  texture.magFilter = THREE.LinearFilter;
  texture.minFilter = THREE.LinearFilter;
  texture.generateMipmaps = false;
  texture.wrapS = THREE.ClampToEdgeWrapping;
  texture.wrapT = THREE.ClampToEdgeWrapping;
  texture.needsUpdate = true;
  const rows = set.atlas.height;
  return {
    texture,
    set,
    rows,
    encoding,
    /** v of a row's centre in this texture as loaded. */
    v: (row) => (reversed ? 1 - (row + 0.5) / rows : (row + 0.5) / rows),
    /** The manifest's row of a page id (or a row number). */
    row: (page) => {
      const entry = typeof page === 'number' ? set.rows[page] : set.rows.find((r) => r.page === page);
      return entry ?? fail(`no row ${page} in ${source}/${encoding}`);
    },
  };
}

async function fetchBytes(url) {
  const response = await fetch(url);
  if (!response.ok) fail(`${url}: HTTP ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
}

/**
 * A 16-bit RGB (or RGBA) PNG, not interlaced, decoded to RGBA Uint16 (alpha 65535 for RGB):
 * the chunks' IDAT data inflated as zlib, then each scanline's filter (PNG spec §9) undone.
 */
export async function decodePng16(bytes) {
  const signature = [137, 80, 78, 71, 13, 10, 26, 10];
  if (!signature.every((b, i) => bytes[i] === b)) fail('not a PNG file');
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let width = 0, height = 0, depth = 0, colour = 0, interlace = 0;
  const idat = [];
  for (let at = 8; at + 8 <= bytes.length; ) {
    const length = view.getUint32(at);
    const type = String.fromCharCode(...bytes.subarray(at + 4, at + 8));
    const data = bytes.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      width = view.getUint32(at + 8);
      height = view.getUint32(at + 12);
      [depth, colour] = [data[8], data[9]];
      interlace = data[12];
    } else if (type === 'IDAT') idat.push(data);
    else if (type === 'IEND') break;
    at += 12 + length;
  }
  if (depth !== 16 || (colour !== 2 && colour !== 6) || interlace !== 0) {
    fail(`expected a non-interlaced 16-bit RGB PNG, got depth ${depth}, colour type ${colour}, interlace ${interlace}`);
  }
  const channels = colour === 2 ? 3 : 4;
  const stream = new Blob(idat).stream().pipeThrough(new DecompressionStream('deflate'));
  const raw = new Uint8Array(await new Response(stream).arrayBuffer());
  const bpp = 2 * channels;
  const stride = width * bpp;
  if (raw.length < height * (stride + 1)) fail('truncated PNG data');
  const pixels = new Uint8Array(height * stride);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const out = pixels.subarray(y * stride, (y + 1) * stride);
    const up = y > 0 ? pixels.subarray((y - 1) * stride, y * stride) : new Uint8Array(stride);
    for (let i = 0; i < stride; i++) {
      const a = i >= bpp ? out[i - bpp] : 0, b = up[i], c = i >= bpp ? up[i - bpp] : 0;
      let predicted = 0;
      if (filter === 1) predicted = a;
      else if (filter === 2) predicted = b;
      else if (filter === 3) predicted = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        predicted = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      } else if (filter !== 0) fail(`unknown PNG filter ${filter}`);
      out[i] = (line[i] + predicted) & 255;
    }
  }
  const rgba = new Uint16Array(width * height * 4);
  for (let p = 0; p < width * height; p++) {
    for (let c = 0; c < 4; c++) rgba[4 * p + c] = c < channels ? (pixels[p * bpp + 2 * c] << 8) | pixels[p * bpp + 2 * c + 1] : 65535;
  }
  return { width, height, rgba };
}

/** `text` with `from` replaced once; fails, naming the three.js revision, when it is not there. */
function replaceOnce(text, from, to, where) {
  const at = text.indexOf(from);
  if (at < 0) fail(`three.js r${THREE.REVISION}: "${from}" not found in ${where}; this module is written for r187`);
  return text.slice(0, at) + to + text.slice(at + from.length);
}

/** three's physical lighting chunk with every Fresnel term read from the LUT (see the header). */
function lutLighting() {
  let chunk = THREE.ShaderChunk.lights_physical_pars_fragment;
  const where = 'lights_physical_pars_fragment';
  // Direct lights: the microfacet term of BRDF_GGX, then the diffuse layer's share.
  chunk = chunk.replace(/(vec3 f0 = material\.specularColorBlended;[^]*?)vec3 F = F_Schlick\( f0, f90, dotVH \);/, '$1vec3 F = nklutFresnel( dotVH );');
  if (!chunk.includes('vec3 F = nklutFresnel( dotVH );')) fail(`three.js r${THREE.REVISION}: BRDF_GGX's Fresnel not found`);
  chunk = replaceOnce(chunk, 'vec3 F = F_Schlick( material.specularColor, material.specularF90, dotVH );', 'vec3 F = nklutFresnel( dotVH );', where);
  // Environment: single and multiple scattering from F_LUT(n·v).
  chunk = replaceOnce(chunk, 'vec3 Fr = specularColor;', 'vec3 Fr = nklutFresnelNV;', where);
  chunk = replaceOnce(chunk, 'vec3 FssEss = Fr * fab.x + specularF90 * fab.y;', 'vec3 FssEss = Fr * ( fab.x + fab.y );', where);
  return chunk;
}

function lutTransmission() {
  return replaceOnce(
    THREE.ShaderChunk.transmission_pars_fragment,
    'vec3 F = EnvironmentBRDF( n, v, specularColor, specularF90, roughness );',
    'vec3 F = nklutFresnel( saturate( dot( n, v ) ) );',
    'transmission_pars_fragment',
  );
}

/** Changes a physical material's fragment shader as the header says. */
export function patchFragmentShader(fragmentShader) {
  let shader = fragmentShader;
  shader = replaceOnce(shader, '#include <common>', `#include <common>\n${NKLUT_GLSL}`, 'the fragment shader');
  shader = replaceOnce(shader, '#include <lights_physical_pars_fragment>', lutLighting(), 'the fragment shader');
  shader = replaceOnce(shader, '#include <transmission_pars_fragment>', lutTransmission(), 'the fragment shader');
  shader = replaceOnce(
    shader,
    '#include <lights_physical_fragment>',
    `#include <lights_physical_fragment>
	nklutCos = saturate( dot( normal, ( isOrthographic ) ? vec3( 0.0, 0.0, 1.0 ) : normalize( vViewPosition ) ) );
	nklutFresnelNV = nklutFresnel( nklutCos );`,
    'the fragment shader',
  );
  shader = replaceOnce(
    shader,
    '#include <dithering_fragment>',
    `#include <dithering_fragment>
	#ifdef NKLUT_OUTPUT_FRESNEL
		gl_FragColor = vec4( nklutFresnelNV, nklutCos );
	#endif`,
    'the fragment shader',
  );
  return shader;
}

/**
 * A MeshPhysicalMaterial whose Fresnel is the LUT row of `page` (a page id or a row number).
 * Defaults by the row's kind: conductors metalness 1; dielectrics metalness 0, white,
 * transmission 1 and ior = the green channel's n (three clamps ior to [1, 2.333]; it only
 * bends the refracted ray here). `parameters` override them (MeshPhysicalMaterial's own).
 */
export function nklutMaterial(lut, page, parameters = {}) {
  const row = lut.row(page);
  const conductor = row.kind === 'conductor';
  const n = row.index_three_channel?.[1]?.n ?? 1.5;
  const defaults = conductor
    ? { color: 0xffffff, metalness: 1, roughness: 0 }
    : { color: 0xffffff, metalness: 0, roughness: 0, transmission: 1, ior: Math.min(Math.max(n, 1), 2.333), thickness: 1 };
  const material = new THREE.MeshPhysicalMaterial({ ...defaults, ...parameters });
  const uniforms = { nklutLut: { value: lut.texture }, nklutV: { value: lut.v(row.row) } };
  material.userData.nklut = { page: row.page, row: row.row, encoding: lut.encoding, uniforms };
  material.onBeforeCompile = (shader) => {
    Object.assign(shader.uniforms, uniforms);
    shader.fragmentShader = patchFragmentShader(shader.fragmentShader);
  };
  material.customProgramCacheKey = () => 'nklut-lut-1';
  return material;
}
