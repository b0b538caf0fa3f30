// Validates glTF files with the Khronos glTF validator (npm package gltf-validator) and prints
// each file's report (issue counts and messages). Exits 1 when any file has an error, 2 when the
// validator cannot be loaded or a file cannot be read.
//   node validate_gltf.js NODE_MODULES_DIR FILE.gltf...
'use strict';
const fs = require('fs');
const path = require('path');

async function main() {
  const [modules, ...files] = process.argv.slice(2);
  if (!modules || files.length === 0) {
    console.error('usage: node validate_gltf.js NODE_MODULES_DIR FILE.gltf...');
    process.exit(2);
  }
  const validator = require(path.join(path.resolve(modules), 'gltf-validator'));
  let failed = false;
  for (const file of files) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      uri: path.basename(file),
      // An export embeds its one buffer (the preview sphere) as a data: URI and references no
      // external buffers or images; any request is an error.
      externalResourceFunction: (uri) => Promise.reject(new Error('unexpected resource ' + uri)),
    });
    const issues = report.issues;
    console.log(JSON.stringify({
      file,
      validator: report.validatorVersion,
      errors: issues.numErrors,
      warnings: issues.numWarnings,
      infos: issues.numInfos,
      hints: issues.numHints,
      messages: issues.messages,
    }));
    if (issues.numErrors > 0) failed = true;
  }
  process.exit(failed ? 1 : 0);
}

main().catch((error) => {
  console.error('validate_gltf: ' + error.message);
  process.exit(2);
});
