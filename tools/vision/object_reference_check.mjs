// Conversion check of the object detector: runs NanoDet's TF.js graph model (the very
// nanodet.json + nanodet.bin Marvin loads) with tfjs's pure-JS CPU backend on the network
// inputs `marvin-vision-eval object-outputs` wrote, and compares the six raw outputs with
// ours (OpenCV DNN, core/vision/tfjs_graph.cpp). Tool time only; never needed at run time.
//
//   node tools/vision/object_reference_check.mjs NODE_DIR MODEL_JSON OUT_DIR
//
// NODE_DIR holds node_modules with @tensorflow/tfjs 4.22.0 (tools/vision/check-conversion
// installs it). Prints, per image and output, the largest absolute difference relative to
// the largest magnitude of the reference output, and the worst over all.
import fs from 'fs';
import { createRequire } from 'module';
import path from 'path';

const [nodeDir, modelJson, dir] = process.argv.slice(2);
const require = createRequire(path.resolve(nodeDir, 'package.json'));
const tf = require('@tensorflow/tfjs');
await tf.setBackend('cpu');
await tf.ready();

const model = JSON.parse(fs.readFileSync(modelJson));
const bin = fs.readFileSync(path.join(path.dirname(modelJson), model.weightsManifest[0].paths[0]));
const net = await tf.loadGraphModel(tf.io.fromMemory({
  modelTopology: model.modelTopology,
  weightSpecs: model.weightsManifest.flatMap((g) => g.weights),
  weightData: bin.buffer.slice(bin.byteOffset, bin.byteOffset + bin.byteLength),
  format: model.format,
  generatedBy: model.generatedBy,
  convertedBy: model.convertedBy,
  signature: model.signature,
}));

const names = ['Identity', 'Identity_1', 'Identity_2', 'Identity_3', 'Identity_4', 'Identity_5'];
const ours = JSON.parse(fs.readFileSync(path.join(dir, 'ours.json')));
let worst = 0;
const samples = {};  // 100 evenly spaced values of each output, for vision_tests' stored reference
for (const image of Object.keys(ours).sort()) {
  const raw = fs.readFileSync(path.join(dir, image + '.input'));
  const input = tf.tensor4d(new Float32Array(raw.buffer, raw.byteOffset, raw.byteLength / 4),
                            [1, 3, 416, 416]);
  const outs = net.execute(input, names);
  const parts = [];
  for (let k = 0; k < names.length; k++) {
    const ref = await outs[k].data();
    const mine = ours[image][k];
    if (mine.length !== ref.length) throw new Error(`${image} ${names[k]}: ${mine.length} values, reference ${ref.length}`);
    let scale = 0, diff = 0;
    for (let i = 0; i < ref.length; i++) {
      scale = Math.max(scale, Math.abs(ref[i]));
      diff = Math.max(diff, Math.abs(ref[i] - mine[i]));
    }
    const rel = diff / scale;
    const step = Math.floor(ref.length / 100);
    (samples[image] ??= []).push({ output: names[k], step, values: Array.from({ length: 100 }, (_, i) => ref[i * step]) });
    worst = Math.max(worst, rel);
    parts.push(`${names[k]} ${rel.toExponential(2)}`);
  }
  console.log(`${image}: relative difference per output: ${parts.join(', ')}`);
}
fs.writeFileSync(path.join(dir, 'reference_samples.json'), JSON.stringify(samples));
console.log(`backend ${tf.getBackend()}, tfjs ${tf.version_core}: worst relative difference ${worst.toExponential(3)} over ${Object.keys(ours).length} images x 6 outputs`);
process.exit(worst < 1e-3 ? 0 : 1);
