// The material viewer's page script (python -m slicecap.viewer, docs/material-viewer.md), inlined
// into the HTML with its data: no network at view time. WebGL 2 draws four panels on one canvas,
// top row the sphere, bottom row the cloth; left the fitted material, right the measured table.
// With SVBRDF maps (data.maps) instead: one panel, the maps' texels on a plane.
// The scene's numbers come from the page data (slicecap.viewer_scene), so that the numpy renderer
// that checks this page (render.render_sphere_point_light) uses the same ones.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("slicecap-data").textContent);
  const scene = data.scene;
  const size = data.panel_size;
  const maps = data.maps;
  const side = maps ? size : 2 * size;
  const canvas = document.getElementById("view");
  canvas.width = side;
  canvas.height = side;
  canvas.style.width = side + "px";
  canvas.style.height = side + "px";
  const state = Object.assign({}, scene.defaults, { exposure: data.exposure });

  function fail(message) {
    const box = document.getElementById("error");
    box.textContent = message;
    box.hidden = false;
    document.title = "slicecap viewer: error";
  }

  // #light=AZ,EL&camera=YAW,PITCH&env=E&exposure=X: a view that can be shared and that the
  // real-browser check sets, so that its screenshot is deterministic.
  function readHash() {
    for (const part of window.location.hash.replace(/^#/, "").split("&")) {
      const [key, value] = part.split("=");
      const numbers = (value || "").split(",").map(Number);
      if (numbers.some((n) => !Number.isFinite(n))) continue;
      if (key === "light" && numbers.length === 2) [state.light_az, state.light_el] = numbers;
      if (key === "camera" && numbers.length === 2) [state.yaw, state.pitch] = numbers;
      if (key === "env" && numbers.length === 1) state.env = numbers[0];
      if (key === "exposure" && numbers.length === 1) state.exposure = numbers[0];
    }
  }
  function writeHash() {
    const r = (x) => Math.round(x * 100) / 100;
    const hash = `#light=${r(state.light_az)},${r(state.light_el)}&camera=${r(state.yaw)},` +
      `${r(state.pitch)}&env=${r(state.env)}&exposure=${state.exposure.toPrecision(4)}`;
    history.replaceState(null, "", hash);
  }

  function bytesOf(base64) { return Uint8Array.from(atob(base64), (c) => c.charCodeAt(0)); }
  function floatsOf(base64) { return new Float32Array(bytesOf(base64).buffer); }

  const gl = canvas.getContext("webgl2", { antialias: false, preserveDrawingBuffer: true });
  if (!gl) {
    fail("This page needs WebGL 2, which this browser does not offer.");
    return;
  }

  // ---- small matrix helpers (column-major, as WebGL takes them) ----
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function cross(a, b) {
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  }
  function normalise(a) { const l = Math.hypot(a[0], a[1], a[2]); return [a[0] / l, a[1] / l, a[2] / l]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function multiply(a, b) {
    const out = new Array(16).fill(0);
    for (let c = 0; c < 4; ++c)
      for (let r = 0; r < 4; ++r)
        for (let k = 0; k < 4; ++k) out[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
    return out;
  }
  function perspective(fovDeg, near, far) {
    const f = 1 / Math.tan((fovDeg * Math.PI) / 360);
    return [f, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) / (near - far), -1,
      0, 0, (2 * far * near) / (near - far), 0];
  }
  function lookAt(eye) {
    const z = normalise(eye);  // the camera looks at the origin, along -z
    const x = normalise(cross([0, 1, 0], z));
    const y = cross(z, x);
    return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -dot(x, eye), -dot(y, eye), -dot(z, eye), 1];
  }
  function orbit(azDeg, elDeg, distance) {
    const az = (azDeg * Math.PI) / 180, el = (elDeg * Math.PI) / 180;
    return [distance * Math.cos(el) * Math.sin(az), distance * Math.sin(el),
      distance * Math.cos(el) * Math.cos(az)];
  }

  // ---- meshes: position, normal, tangent per vertex ----
  function grid(columns, rows, vertexOf) {
    const vertices = [], indices = [];
    for (let j = 0; j <= rows; ++j)
      for (let i = 0; i <= columns; ++i) vertices.push(...vertexOf(i / columns, j / rows));
    for (let j = 0; j < rows; ++j)
      for (let i = 0; i < columns; ++i) {
        const a = j * (columns + 1) + i, b = a + 1, c = a + columns + 1, d = c + 1;
        indices.push(a, c, b, b, c, d);
      }
    return { vertices: new Float32Array(vertices), indices: new Uint32Array(indices) };
  }
  // The sphere's shader takes its normal and tangent from the position (exact on the sphere).
  const sphereMesh = grid(128, 64, (u, v) => {
    const phi = 2 * Math.PI * u, theta = Math.PI * v;
    const p = [Math.sin(theta) * Math.sin(phi), Math.cos(theta), Math.sin(theta) * Math.cos(phi)];
    return [...p, ...p, 1, 0, 0];
  });
  // A cloth-like sheet: folds running mostly down it; the tangent (the table's azimuth 0) is
  // the sheet's horizontal thread direction dP/du.
  const cloth = scene.cloth;
  const clothMesh = grid(128, 128, (u, v) => {
    const x = 2 * u - 1, y = 1 - 2 * v;
    const phase = cloth.fold_frequency * x + cloth.fold_skew * y;
    const p = [cloth.half_width * x, cloth.half_width * y,
      cloth.fold_depth * Math.sin(phase) + cloth.ripple_depth * Math.sin(cloth.ripple_frequency * y)];
    const du = [cloth.half_width, 0, cloth.fold_depth * cloth.fold_frequency * Math.cos(phase)];
    const dv = [0, cloth.half_width, cloth.fold_depth * cloth.fold_skew * Math.cos(phase) +
      cloth.ripple_depth * cloth.ripple_frequency * Math.cos(cloth.ripple_frequency * y)];
    const n = normalise(cross(du, dv));
    return [...p, ...n, ...normalise(du)];
  });

  function compile(kind, source) {
    const shader = gl.createShader(kind);
    gl.shaderSource(shader, source);
    gl.compileShader(shader);
    if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS))
      throw new Error("shader: " + gl.getShaderInfoLog(shader));
    return shader;
  }
  let program;
  try {
    program = gl.createProgram();
    const text = (id) => document.getElementById(id).textContent.trim();
    gl.attachShader(program, compile(gl.VERTEX_SHADER, text("vertex-shader")));
    gl.attachShader(program, compile(gl.FRAGMENT_SHADER, text("fragment-shader")));
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS))
      throw new Error("link: " + gl.getProgramInfoLog(program));
  } catch (e) {
    fail("WebGL: " + e.message);
    return;
  }
  gl.useProgram(program);
  const uniform = (name) => gl.getUniformLocation(program, name);

  function upload(mesh) {
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const buffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.bufferData(gl.ARRAY_BUFFER, mesh.vertices, gl.STATIC_DRAW);
    ["a_position", "a_normal", "a_tangent"].forEach((name, k) => {
      const location = gl.getAttribLocation(program, name);
      gl.enableVertexAttribArray(location);
      gl.vertexAttribPointer(location, 3, gl.FLOAT, false, 36, 12 * k);
    });
    const indices = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, indices);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, mesh.indices, gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    return { vao, count: mesh.indices.length };
  }
  // The maps' plane (slicecap.viewer_plane): z = 0, normal +z, tangent +x.
  const half = maps ? maps.half_width : 1;
  const planeMesh = grid(1, 1, (u, v) => [half * (2 * u - 1), half * (1 - 2 * v), 0, 0, 0, 1, 1, 0, 0]);
  const meshes = { sphere: upload(sphereMesh), cloth: upload(clothMesh), plane: upload(planeMesh) };

  // Textures read with texelFetch only: no filtering, no mipmaps.
  gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
  function texture(unit, name, internal, width, height, format, type, pixels) {
    gl.activeTexture(gl.TEXTURE0 + unit);
    gl.bindTexture(gl.TEXTURE_2D, gl.createTexture());
    gl.texImage2D(gl.TEXTURE_2D, 0, internal, width, height, 0, format, type, pixels);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.uniform1i(uniform(name), unit);
  }
  // The measured table: an 81 x 81 RGB float texture, row = light index, column = view index.
  if (data.table) {
    texture(0, "u_table", gl.RGB32F, 81, 81, gl.RGB, gl.FLOAT, floatsOf(data.table.values_base64));
  }
  const tableAlbedo = data.table ? floatsOf(data.table.albedo_base64) : null;
  // The maps' bytes as the PNGs hold them (packed by slicecap.viewer), one RGBA8 texture each,
  // and the GGX lobe's albedo table (A, B) shared by all texels (slicecap.albedo_table).
  gl.uniform1i(uniform("u_maps"), maps ? 1 : 0);
  if (maps) {
    const n = maps.resolution;
    const rgba8 = (unit, name, base64) =>
      texture(unit, name, gl.RGBA8, n, n, gl.RGBA, gl.UNSIGNED_BYTE, bytesOf(base64));
    rgba8(1, "u_mapBase", maps.base_base64);
    rgba8(2, "u_mapSpecular", maps.specular_base64);
    rgba8(3, "u_mapShape", maps.shape_base64);
    // normal.png's R, G bytes (its B, z, follows from them): an 8-bit texture, as the others.
    texture(5, "u_mapNormal", gl.RG8, n, n, gl.RG, gl.UNSIGNED_BYTE, bytesOf(maps.normal_base64));
    const albedo = maps.albedo_table;
    texture(4, "u_albedoTable", gl.RG32F, albedo.width, albedo.height, gl.RG, gl.FLOAT,
            floatsOf(albedo.base64));
    gl.uniform1f(uniform("u_diffuseWeight"), albedo.diffuse_weight);
    gl.uniform4iv(uniform("u_albedoNodes"), albedo.nodes);
    gl.uniform1f(uniform("u_albedoThetaMaxDeg"), albedo.theta_max_deg);
    gl.uniform1i(uniform("u_mapResolution"), n);
    gl.uniform1f(uniform("u_iorF0"), maps.ior_f0);
    gl.uniform1f(uniform("u_halfWidth"), maps.half_width);
    gl.uniform3fv(uniform("u_marker"), maps.marker.map((c) => c / 255));
  }
  const fit = data.material;
  if (fit) {
    const p = fit.parameters;
    gl.uniform3fv(uniform("u_diffuse"), p.diffuse_albedo);
    gl.uniform3fv(uniform("u_f0"), p.specular_f0);
    gl.uniform1f(uniform("u_f90"), p.specular_f90);
    gl.uniform1f(uniform("u_alphaT"), p.alpha_tangent);
    gl.uniform1f(uniform("u_alphaB"), p.alpha_bitangent);
    gl.uniform1f(uniform("u_tangentRad"), (p.tangent_deg * Math.PI) / 180);
    // The model names its terms: "ggx", "ggx+sheen", "ggx+coat", "ggx+sheen+coat".
    const terms = fit.model.split("+");
    gl.uniform1i(uniform("u_sheen"), terms.includes("sheen") ? 1 : 0);
    gl.uniform3fv(uniform("u_sheenColour"), p.sheen_colour || [0, 0, 0]);
    gl.uniform1f(uniform("u_sheenRoughness"), p.sheen_roughness || 0.5);
    // The sheen's form (docs/material-fit.md): KHR_materials_sheen's, with the directional albedo
    // table E its scaling of the rest reads (computed by slicecap.viewer as lib/fit does), or the
    // additive one of format-version-1 fits, which come without the table.
    const sheenAlbedo = fit.sheen_albedo;
    gl.uniform1i(uniform("u_sheenKhr"), sheenAlbedo ? 1 : 0);
    if (sheenAlbedo) {
      texture(6, "u_sheenAlbedo", gl.R32F, sheenAlbedo.cosines, sheenAlbedo.roughnesses, gl.RED,
              gl.FLOAT, floatsOf(sheenAlbedo.base64));
      gl.uniform2i(uniform("u_sheenAlbedoNodes"), sheenAlbedo.cosines, sheenAlbedo.roughnesses);
      gl.uniform2f(uniform("u_sheenAlbedoRoughness"), sheenAlbedo.min_roughness,
                   sheenAlbedo.max_roughness);
    }
    gl.uniform1i(uniform("u_coat"), terms.includes("coat") ? 1 : 0);
    gl.uniform1f(uniform("u_coatWeight"), p.coat_weight || 0);
    gl.uniform1f(uniform("u_coatAlpha"), p.coat_alpha || 0.1);
  }
  const fitAlbedo = fit ? floatsOf(fit.albedo_base64) : null;

  function render() {
    const eye = orbit(state.yaw, state.pitch, scene.camera_distance);
    const viewProjection = multiply(perspective(scene.fov_deg, 0.1, 20), lookAt(eye));
    gl.uniformMatrix4fv(uniform("u_viewProjection"), false, viewProjection);
    gl.uniform3fv(uniform("u_camera"), eye);
    gl.uniform3fv(uniform("u_light"), orbit(state.light_az, state.light_el, scene.light_distance));
    gl.uniform1f(uniform("u_intensity"), scene.light_intensity);
    gl.uniform1f(uniform("u_env"), state.env);
    gl.uniform1f(uniform("u_exposure"), state.exposure);
    gl.enable(gl.SCISSOR_TEST);
    gl.enable(gl.DEPTH_TEST);
    gl.disable(gl.CULL_FACE);
    const panels = maps ? [["plane", 0, 0]]
      : [["sphere", 0, 1], ["sphere", 1, 1], ["cloth", 0, 0], ["cloth", 1, 0]];
    for (const [shape, mode, row] of panels) {
      gl.viewport(mode * size, row * size, size, size);
      gl.scissor(mode * size, row * size, size, size);
      gl.clearColor(0.09, 0.09, 0.09, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      if (mode === 0 && !fit && !maps) continue;
      gl.uniform1i(uniform("u_mode"), mode);
      gl.uniform1i(uniform("u_sphere"), shape === "sphere" ? 1 : 0);
      if (!maps) gl.uniform3fv(uniform("u_albedo"), mode === 0 ? fitAlbedo : tableAlbedo);
      gl.bindVertexArray(meshes[shape].vao);
      gl.drawElements(gl.TRIANGLES, meshes[shape].count, gl.UNSIGNED_INT, 0);
    }
    gl.bindVertexArray(null);
    document.getElementById("state").textContent =
      `light azimuth ${state.light_az.toFixed(1)} deg, elevation ${state.light_el.toFixed(1)} deg; ` +
      `camera yaw ${state.yaw.toFixed(1)} deg, pitch ${state.pitch.toFixed(1)} deg`;
    exposureInput.value = Math.log2(state.exposure / data.exposure);
    envInput.value = state.env;
  }

  // ---- controls: drag = light, shift-drag or right-drag = camera; sliders; reset ----
  const exposureInput = document.getElementById("exposure");
  const envInput = document.getElementById("env");
  let frame = 0;
  function update() {
    if (frame) return;
    frame = requestAnimationFrame(() => { frame = 0; render(); writeHash(); });
  }
  let drag = null;
  canvas.addEventListener("contextmenu", (e) => e.preventDefault());
  canvas.addEventListener("pointerdown", (e) => {
    drag = { x: e.clientX, y: e.clientY, camera: e.shiftKey || e.button === 2 };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    const clampEl = (x) => Math.max(-89, Math.min(89, x));
    if (drag.camera) {
      state.yaw -= dx * 0.5;
      state.pitch = clampEl(state.pitch + dy * 0.5);
    } else {
      state.light_az += dx * 0.5;
      state.light_el = clampEl(state.light_el - dy * 0.5);
    }
    update();
  });
  canvas.addEventListener("pointerup", () => { drag = null; });
  exposureInput.addEventListener("input", () => {
    state.exposure = data.exposure * Math.pow(2, Number(exposureInput.value));
    update();
  });
  envInput.addEventListener("input", () => { state.env = Number(envInput.value); update(); });
  document.getElementById("reset").addEventListener("click", () => {
    Object.assign(state, scene.defaults, { exposure: data.exposure });
    update();
  });
  window.addEventListener("hashchange", () => { readHash(); render(); });

  readHash();
  render();
  document.title = "slicecap viewer: " + (maps ? maps.name : data.table.name);
  document.body.dataset.rendered = "yes";
})();
