// Runs the Khronos glTF validator (npm gltf-validator, pinned in package.json) on one .gltf or .glb
// and prints its report as JSON on stdout. Exit 0 when the report has no errors, 1 when it has,
// 2 when the file cannot be read. Used by python/tests/test_material_export.py.
import { readFile } from "node:fs/promises";
import path from "node:path";
import validator from "gltf-validator";

const file = process.argv[2];
if (!file) {
  console.error("usage: node validate-gltf.mjs FILE.gltf|FILE.glb");
  process.exit(2);
}
let bytes;
try {
  bytes = new Uint8Array(await readFile(file));
} catch (e) {
  console.error(`${file}: cannot be read (${e.message})`);
  process.exit(2);
}
const report = await validator.validateBytes(bytes, {
  uri: path.basename(file),
  maxIssues: 100,
  // The slicecap exports are self-contained (a data URI or a GLB buffer): nothing external to load.
  externalResourceFunction: (uri) => Promise.reject(new Error(`external resource ${uri} not expected`)),
});
console.log(JSON.stringify(report, null, 1));
process.exit(report.issues.numErrors > 0 ? 1 : 0);
