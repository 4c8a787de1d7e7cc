// Validate a glTF 2.0 file with the Khronos glTF-Validator (npm `gltf-validator`).
//
// Usage: node validate_gltf.js FILE.gltf
// External resources (the .bin buffer) are read next to the file. Prints the validator's
// summary as one JSON line: {"errors": n, "warnings": n, "infos": n, "messages": [...],
// "validatorVersion": "..."}; exit status 0 when there are no errors, 1 otherwise.
const fs = require("fs");
const path = require("path");
const validator = require("gltf-validator");

const file = process.argv[2];
const asset = fs.readFileSync(file);
validator
  .validateBytes(new Uint8Array(asset), {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)), (error, data) => (error ? reject(error.toString()) : resolve(new Uint8Array(data))));
      }),
  })
  .then((report) => {
    const issues = report.issues;
    const summary = {
      errors: issues.numErrors,
      warnings: issues.numWarnings,
      infos: issues.numInfos,
      messages: issues.messages.filter((m) => m.severity <= 1).slice(0, 20),
      validatorVersion: report.validatorVersion,
    };
    console.log(JSON.stringify(summary));
    process.exit(issues.numErrors === 0 ? 0 : 1);
  })
  .catch((error) => {
    console.log(JSON.stringify({ errors: -1, failure: String(error) }));
    process.exit(2);
  });
