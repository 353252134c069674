// three.js drawing a glTF material's direct light by the Khronos texts, for slicecap's exports
// (docs/material-export.md, "three.js"). three.js 0.187's MeshPhysicalMaterial departs from them in
// four places that move a slicecap fit's render (docs/results/2026-12-06-export-spec.md); this
// module replaces exactly those lines of its shader chunks, through the material's
// onBeforeCompile, and throws when a line is not found (another three.js revision), so a change
// upstream is seen, not silently drawn the old way:
//
// 1. The sheen's visibility: three.js's V_Neubelt (lights_physical_pars_fragment.glsl.js) becomes
//    KHR_materials_sheen's "Charlie" visibility (its README, "Sheen visibility"; Estevez and Kulla
//    2017), which slicecap's fit and the specification's evaluator take.
// 2. The base's albedo scaling under a direct light: three.js's IBLSheenBRDF curve fit becomes the
//    sheen's own directional albedo E (KHR_materials_sheen, "Albedo scaling"): the hemisphere's
//    integral of D_charlie V_charlie cos, tabulated here at 33 cosines for the material's sheen
//    roughness (the quadrature of python/src/slicecap/fitted_material.py, sheen_albedo_table).
// 3. The diffuse under the specular: three.js dims it per channel by (1 - F); KHR_materials_specular
//    ("Implementation", fresnel_mix) by 1 - max_value(F).
// 4. The direct specular's multiple-scattering compensation (lights_fragment_begin.glsl.js,
//    multiScatteringCompensation), which no glTF text has, is 1.
//
// Image-based and ambient light are left as three.js draws them (the sheen's IBL term keeps its
// curve fit). E is computed when the program compiles, from material.sheenRoughness then.
//
//   import * as THREE from 'three';
//   import { drawBySpecification } from './threejs_spec.js';
//   drawBySpecification(mesh.material, THREE);

export const SHEEN_ALBEDO_COSINES = 33;

const CHARLIE_GLSL = /* glsl */`
// KHR_materials_sheen, "Sheen visibility" (the Charlie visibility's lambda; slicecap threejs_spec.js)
float slicecapSheenL( const in float x, const in float alphaG ) {
	float oneMinusAlphaSq = ( 1.0 - alphaG ) * ( 1.0 - alphaG );
	float a = mix( 21.5473, 25.3245, oneMinusAlphaSq );
	float b = mix( 3.82987, 3.32435, oneMinusAlphaSq );
	float c = mix( 0.19823, 0.16801, oneMinusAlphaSq );
	float d = mix( -1.97760, -1.27393, oneMinusAlphaSq );
	float e = mix( -4.32054, -4.85967, oneMinusAlphaSq );
	return a / ( 1.0 + b * pow( x, c ) ) + d * x + e;
}
float slicecapLambdaSheen( const in float cosTheta, const in float alphaG ) {
	return abs( cosTheta ) < 0.5 ? exp( slicecapSheenL( cosTheta, alphaG ) )
		: exp( 2.0 * slicecapSheenL( 0.5, alphaG ) - slicecapSheenL( 1.0 - cosTheta, alphaG ) );
}
float V_Charlie( const in float dotNV, const in float dotNL, const in float sheenRoughness ) {
	float alphaG = pow2( sheenRoughness );
	return 1.0 / max( ( 1.0 + slicecapLambdaSheen( dotNV, alphaG ) + slicecapLambdaSheen( dotNL, alphaG ) )
		* ( 4.0 * dotNV * dotNL ), EPSILON );
}
uniform float slicecapSheenAlbedo[ ${SHEEN_ALBEDO_COSINES} ];
float slicecapSheenAlbedoAt( const in float cosTheta ) {
	float x = saturate( cosTheta ) * ${SHEEN_ALBEDO_COSINES - 1}.0;
	int i = int( min( floor( x ), ${SHEEN_ALBEDO_COSINES - 2}.0 ) );
	return mix( slicecapSheenAlbedo[ i ], slicecapSheenAlbedo[ i + 1 ], x - float( i ) );
}
`;

// [part, chunk, the line as three.js 0.187 has it, what it becomes]; the parts are named as
// python/checks/threejs_brdf.py's DEVIATIONS.
const REPLACEMENTS = [
  ['visibility', 'lights_physical_pars_fragment', 'vec3 BRDF_Sheen(', CHARLIE_GLSL + 'vec3 BRDF_Sheen('],
  ['visibility', 'lights_physical_pars_fragment', 'float V = V_Neubelt( dotNV, dotNL );',
   'float V = V_Charlie( dotNV, dotNL, sheenRoughness );'],
  ['sheen_albedo', 'lights_physical_pars_fragment',
   'float sheenAlbedoV = IBLSheenBRDF( geometryNormal, geometryViewDir, material.sheenRoughness );',
   'float sheenAlbedoV = slicecapSheenAlbedoAt( dot( geometryNormal, geometryViewDir ) );'],
  ['sheen_albedo', 'lights_physical_pars_fragment',
   'float sheenAlbedoL = IBLSheenBRDF( geometryNormal, directLight.direction, material.sheenRoughness );',
   'float sheenAlbedoL = slicecapSheenAlbedoAt( dot( geometryNormal, directLight.direction ) );'],
  ['diffuse_dimming', 'lights_physical_pars_fragment',
   'reflectedLight.directDiffuse += irradiance * diffuseBRDF * ( 1.0 - F );',
   'reflectedLight.directDiffuse += irradiance * diffuseBRDF * ( 1.0 - max3( F ) );'],
  ['multiscatter', 'lights_fragment_begin',
   'material.multiScatteringCompensation = 1.0 + material.specularColorBlended * ( 1.0 / EssMs - 1.0 );',
   'material.multiScatteringCompensation = vec3( 1.0 );'],
];

export const PARTS = ['visibility', 'sheen_albedo', 'diffuse_dimming', 'multiscatter'];

/// The two chunks with the replacements made (of `parts` only, for measuring each one's share; the
/// charlie visibility's functions come with 'visibility'). Throws an Error naming the chunk and the
/// line when a line is not in it exactly once.
export function specificationChunks(shaderChunk, revision = '', parts = PARTS) {
  const chunks = {
    lights_physical_pars_fragment: shaderChunk.lights_physical_pars_fragment,
    lights_fragment_begin: shaderChunk.lights_fragment_begin,
  };
  for (const [part, name, from, to] of REPLACEMENTS) {
    if (!parts.includes(part)) continue;
    const text = chunks[name];
    const at = text.indexOf(from);
    if (at < 0 || text.indexOf(from, at + 1) >= 0) {
      throw new Error(`three.js ${revision}: ${name} has ${at < 0 ? 'no' : 'more than one'} ` +
                      `"${from}"; slicecap's threejs_spec.js follows three.js 0.187`);
    }
    chunks[name] = text.slice(0, at) + to + text.slice(at + from.length);
  }
  return chunks;
}

function lambdaSheen(cosTheta, alphaG) {
  const w = (1 - alphaG) * (1 - alphaG);
  const mix = (x, y) => x + (y - x) * w;
  const l = (x) => mix(21.5473, 25.3245) / (1 + mix(3.82987, 3.32435) * Math.pow(x, mix(0.19823, 0.16801)))
    + mix(-1.97760, -1.27393) * x + mix(-4.32054, -4.85967);
  return Math.abs(cosTheta) < 0.5 ? Math.exp(l(cosTheta)) : Math.exp(2 * l(0.5) - l(1 - cosTheta));
}

/// E(mu) at mu = i / 32, i = 0..32: the integral over the hemisphere of D_charlie V_charlie cos of
/// alpha_g (= sheenRoughness^2), by the midpoint rule over theta (64) and phi (64 over [0, pi],
/// doubled), mu floored at 1e-3: python/src/slicecap/fitted_material.py's sheen_albedo_table.
export function sheenAlbedo(alphaG) {
  const steps = 64, out = new Float32Array(SHEEN_ALBEDO_COSINES);
  const alpha = Math.max(alphaG, 1e-7);
  for (let i = 0; i < SHEEN_ALBEDO_COSINES; ++i) {
    const mu = Math.max(i / (SHEEN_ALBEDO_COSINES - 1), 1e-3), sinV = Math.sqrt(1 - mu * mu);
    const lambdaV = lambdaSheen(mu, alpha);
    let total = 0;
    for (let t = 0; t < steps; ++t) {
      const theta = (t + 0.5) * (Math.PI / 2) / steps;
      const cosL = Math.cos(theta), sinL = Math.sin(theta);
      const visibility = 1 / ((1 + lambdaV + lambdaSheen(cosL, alpha)) * (4 * mu * cosL));
      for (let p = 0; p < steps; ++p) {
        const phi = (p + 0.5) * Math.PI / steps;
        const hx = sinL * Math.cos(phi) + sinV, hy = sinL * Math.sin(phi), hz = cosL + mu;
        const cosH2 = hz * hz / (hx * hx + hy * hy + hz * hz);
        const d = (2 + 1 / alpha) * Math.pow(Math.max(1 - cosH2, 0), 0.5 / alpha) / (2 * Math.PI);
        total += d * visibility * cosL * sinL;
      }
    }
    out[i] = 2 * total * (Math.PI / 2 / steps) * (Math.PI / steps);
  }
  return out;
}

/// Makes a MeshPhysicalMaterial draw its direct light by the specification (the four changes
/// above, or those of `parts`). `three` is the three.js module (its ShaderChunk and REVISION).
/// Throws as specificationChunks, before any render.
export function drawBySpecification(material, three, parts = PARTS) {
  const chunks = specificationChunks(three.ShaderChunk, three.REVISION, parts);
  material.onBeforeCompile = (shader) => {
    const roughness = Math.min(Math.max(material.sheenRoughness ?? 0, 1e-4), 1);
    shader.uniforms.slicecapSheenAlbedo = { value: sheenAlbedo(roughness * roughness) };
    shader.fragmentShader = shader.fragmentShader
      .replace('#include <lights_physical_pars_fragment>', chunks.lights_physical_pars_fragment)
      .replace('#include <lights_fragment_begin>', chunks.lights_fragment_begin);
  };
  material.customProgramCacheKey = () => 'slicecap-gltf-specification:' + parts.join(',');
  material.needsUpdate = true;
}
