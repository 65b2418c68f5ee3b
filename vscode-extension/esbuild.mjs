// Bundles the extension (src/extension.ts and vscode-languageclient) into dist/extension.js:
// one file loads faster than node_modules, and the .vsix then ships no node_modules at all.
import * as esbuild from 'esbuild';

await esbuild.build({
  entryPoints: ['src/extension.ts'],
  bundle: true,
  outfile: 'dist/extension.js',
  external: ['vscode'],
  format: 'cjs',
  platform: 'node',
  target: 'node18',
  sourcemap: true,
  minify: process.argv.includes('--minify'),
  logLevel: 'warning',
});
