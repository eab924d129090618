// Runs the original ONNX graphs (melspectrogram.onnx, embedding_model.onnx) with onnxruntime's
// CPU provider on what marvin-kws-embed fed our C++ code, and prints the largest relative
// difference per file (largest absolute difference / largest magnitude of the reference).
// Usage: node reference_check.mjs TOOLS_DIR MODELS_DIR DUMP_DIR [KEEP_DIR]
// KEEP_DIR: also write NAME.ref.json with the reference's first numbers (for tests/kws/data).
import { createRequire } from 'module';
import fs from 'fs';
import path from 'path';

const [toolsDir, modelsDir, dumpDir, keepDir] = process.argv.slice(2);
const require = createRequire(path.join(toolsDir, 'package.json'));
const ort = require('onnxruntime-node');

const floats = (file) => {
  const b = fs.readFileSync(file);
  return new Float32Array(b.buffer, b.byteOffset, b.length / 4);
};
const compare = (ours, ref) => {
  let diff = 0, mag = 0;
  for (let i = 0; i < ref.length; i++) {
    diff = Math.max(diff, Math.abs(ours[i] - ref[i]));
    mag = Math.max(mag, Math.abs(ref[i]));
  }
  return { diff, rel: diff / mag };
};

const mel = await ort.InferenceSession.create(path.join(modelsDir, 'melspectrogram.onnx'));
const emb = await ort.InferenceSession.create(path.join(modelsDir, 'embedding_model.onnx'));
let worstMel = 0, worstEmb = 0, count = 0;
for (const f of fs.readdirSync(dumpDir).filter((f) => f.endsWith('.samples.f32')).sort()) {
  const name = f.replace('.samples.f32', '');
  const samples = floats(path.join(dumpDir, f));
  const melOut = await mel.run({ [mel.inputNames[0]]: new ort.Tensor('float32', samples, [1, samples.length]) });
  const melRef = melOut[mel.outputNames[0]].data;
  const ourMel = floats(path.join(dumpDir, `${name}.mel.f32`));
  if (ourMel.length !== melRef.length) throw new Error(`${name}: ${ourMel.length} mel values, onnxruntime ${melRef.length}`);
  const m = compare(ourMel, melRef);
  const windows = floats(path.join(dumpDir, `${name}.windows.f32`));
  const n = windows.length / (76 * 32);
  const embOut = await emb.run({ [emb.inputNames[0]]: new ort.Tensor('float32', windows, [n, 76, 32, 1]) });
  const embRef = embOut[emb.outputNames[0]].data;
  const ourEmb = floats(path.join(dumpDir, `${name}.emb.f32`));
  if (ourEmb.length !== embRef.length) throw new Error(`${name}: ${ourEmb.length} embedding values, onnxruntime ${embRef.length}`);
  const e = compare(ourEmb, embRef);
  console.log(`${name}: mel ${melRef.length / 32} frames, largest difference ${m.diff.toExponential(3)} (relative ${m.rel.toExponential(3)}); ` +
              `embedding ${n} windows, largest difference ${e.diff.toExponential(3)} (relative ${e.rel.toExponential(3)})`);
  worstMel = Math.max(worstMel, m.rel);
  worstEmb = Math.max(worstEmb, e.rel);
  count++;
  if (keepDir) {
    fs.mkdirSync(keepDir, { recursive: true });
    fs.writeFileSync(path.join(keepDir, `${name}.ref.json`), JSON.stringify({
      samples: samples.length,
      mel_frames: melRef.length / 32,
      mel_first: Array.from(melRef.slice(0, 320)),
      windows: n,
      embedding_first: Array.from(embRef.slice(0, 96 * Math.min(n, 4))),
    }) + '\n');
  }
}
console.log(`onnxruntime-node ${ort.env.versions?.common ?? '1.20.1'} (cpu): worst relative difference mel ${worstMel.toExponential(3)}, embedding ${worstEmb.toExponential(3)} over ${count} files`);
