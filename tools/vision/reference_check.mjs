// Conversion check: runs face-api.js's own FaceRecognitionNet (the npm package's JavaScript,
// with tfjs's pure-JS CPU backend) on the face chips `marvin-vision-eval chips` wrote, and
// compares with our C++ embeddings (ours.json). Tool time only; never needed at run time.
//
//   node tools/vision/reference_check.mjs NODE_DIR CHIPS_DIR
//
// NODE_DIR holds node_modules with @vladmandic/face-api 1.7.15 and @tensorflow/tfjs 4.22.0
// (tools/vision/check-conversion installs them). Prints, per chip, the largest absolute
// difference relative to the largest magnitude of the reference embedding, and the worst.
import fs from 'fs';
import { createRequire } from 'module';
import path from 'path';

const [nodeDir, chips] = process.argv.slice(2);
// face-api's CommonJS build for node (it registers the wasm backend too; we pick 'cpu').
const require = createRequire(path.resolve(nodeDir, 'package.json'));
const tf = require('@tensorflow/tfjs');
const faceapi = require('@vladmandic/face-api/dist/face-api.node-wasm.js');
const pkg = path.dirname(require.resolve('@vladmandic/face-api/package.json'));
await tf.setBackend('cpu');
await tf.ready();

const manifest = JSON.parse(fs.readFileSync(path.join(pkg, 'model/face_recognition_model-weights_manifest.json')));
const bin = fs.readFileSync(path.join(pkg, 'model/face_recognition_model.bin'));
const weightMap = tf.io.decodeWeights(bin.buffer.slice(bin.byteOffset, bin.byteOffset + bin.byteLength),
                                      manifest[0].weights);
const net = new faceapi.FaceRecognitionNet();
net.loadFromWeightMap(weightMap);

const ours = JSON.parse(fs.readFileSync(path.join(chips, 'ours.json')));
const reference = {};
let worst = 0;
for (const name of Object.keys(ours).sort()) {
  const rgb = fs.readFileSync(path.join(chips, name + '.rgb'));
  const input = tf.tensor4d(Float32Array.from(rgb), [1, 150, 150, 3]);
  const out = net.forwardInput(await faceapi.toNetInput(input));
  const ref = Array.from(await out.data());
  reference[name] = ref;
  const scale = Math.max(...ref.map(Math.abs));
  let maxDiff = 0;
  for (let i = 0; i < ref.length; i++) maxDiff = Math.max(maxDiff, Math.abs(ref[i] - ours[name][i]));
  const rel = maxDiff / scale;
  worst = Math.max(worst, rel);
  console.log(`${name}: largest difference ${maxDiff.toExponential(3)} (relative ${rel.toExponential(3)})`);
}
fs.writeFileSync(path.join(chips, 'reference.json'), JSON.stringify(reference));
console.log(`backend ${tf.getBackend()}, tfjs ${tf.version_core}: worst relative difference ${worst.toExponential(3)} over ${Object.keys(ours).length} faces`);
process.exit(worst < 1e-3 ? 0 : 1);
