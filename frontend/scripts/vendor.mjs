// Copy the libraries and map data the page loads into frontend/vendor/ (run by `npm ci` as postinstall).
// The page then loads nothing from the internet: every file it needs is one of ours or one of these copies.
import { cpSync, mkdirSync, rmSync, writeFileSync, readFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const modules = join(root, "node_modules");
const vendor = join(root, "vendor");

// [package, file inside the package, name under vendor/]
const FILES = [
  ["leaflet", "dist/leaflet.js", "leaflet/leaflet.js"],
  ["leaflet", "dist/leaflet.css", "leaflet/leaflet.css"],
  ["leaflet", "dist/images", "leaflet/images"],
  ["d3-array", "dist/d3-array.min.js", "d3-array.min.js"],
  ["d3-geo", "dist/d3-geo.min.js", "d3-geo.min.js"],
  ["topojson-client", "dist/topojson-client.min.js", "topojson-client.min.js"],
  ["world-atlas", "countries-50m.json", "world/countries-50m.json"],
  ["world-atlas", "land-50m.json", "world/land-50m.json"],
  ["world-atlas", "countries-110m.json", "world/countries-110m.json"],
  ["world-atlas", "land-110m.json", "world/land-110m.json"],
];

rmSync(vendor, { recursive: true, force: true });
const versions = {};
for (const [pkg, from, to] of FILES) {
  const target = join(vendor, to);
  mkdirSync(dirname(target), { recursive: true });
  cpSync(join(modules, pkg, from), target, { recursive: true });
  versions[pkg] = JSON.parse(readFileSync(join(modules, pkg, "package.json"), "utf8")).version;
}
writeFileSync(join(vendor, "VERSIONS.json"), JSON.stringify(versions, null, 2) + "\n");
console.log(`vendor/: ${FILES.length} entries from ${Object.keys(versions).join(", ")}`);
