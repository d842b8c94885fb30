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
  // the API's documentation pages (/docs, /redoc), served by the service instead of a CDN
  ["swagger-ui-dist", "swagger-ui-bundle.js", "swagger-ui/swagger-ui-bundle.js"],
  ["swagger-ui-dist", "swagger-ui.css", "swagger-ui/swagger-ui.css"],
  ["redoc", "bundles/redoc.standalone.js", "redoc/redoc.standalone.js"],
];

rmSync(vendor, { recursive: true, force: true });
const versions = {};
for (const [pkg, from, to] of FILES) {
  const target = join(vendor, to);
  mkdirSync(dirname(target), { recursive: true });
  cpSync(join(modules, pkg, from), target, { recursive: true });
  versions[pkg] = JSON.parse(readFileSync(join(modules, pkg, "package.json"), "utf8")).version;
}
// Redoc's one address on the internet, its "powered by" logo, is blanked: the image then fails and Redoc hides it
const redoc = join(vendor, "redoc/redoc.standalone.js");
const logo = "https://cdn.redoc.ly/redoc/logo-mini.svg";
const bundle = readFileSync(redoc, "utf8");
if (!bundle.includes(logo)) throw new Error(`${redoc}: ${logo} not found (a new Redoc: look for its internet addresses)`);
writeFileSync(redoc, bundle.replaceAll(logo, "data:,"));
writeFileSync(join(vendor, "VERSIONS.json"), JSON.stringify(versions, null, 2) + "\n");
console.log(`vendor/: ${FILES.length} entries from ${Object.keys(versions).join(", ")}`);
