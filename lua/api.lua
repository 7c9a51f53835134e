-- The scenario API as data: every public function with its fields, types,
-- units, ranges, docs and an example. check.lua checks arguments against it;
-- scripts/lua_api_docs.lua renders docs/lua-api.md and docs/softcut.d.lua from it (tests
-- compare both files with the rendering). Units are SI: m, s, N, Pa, Hz, rad.
local function F(name, type, doc, opt)
  local f = { name = name, type = type, doc = doc }
  for k, v in pairs(opt or {}) do f[k] = v end
  return f
end

local region_fields = {
  F("label", "integer", "tets with this mesh label"),
  F("sphere", "Sphere", "tets whose centroid lies in the sphere"),
  F("box", "Box", "tets whose centroid lies in the axis-aligned box"),
  F("halfspace", "HalfSpace", "tets whose centroid lies on the normal's side of the plane"),
  F("tets", "integer[]", "explicit 0-based tet ids", { ge = 0 }),
}

local function with(list, ...)
  local out = {}
  for _, f in ipairs(list) do out[#out + 1] = f end
  for _, f in ipairs({ ... }) do out[#out + 1] = f end
  return out
end

local api = {}

-- Plain tables used as field values (checked recursively).
api.structs = {
  { name = "Sphere", summary = "A ball.", fields = {
      F("center", "vec3", "center", { unit = "m", required = true }),
      F("radius", "number", "radius", { unit = "m", gt = 0, required = true }) } },
  { name = "Box", summary = "An axis-aligned box, bounds inclusive.", fields = {
      F("min", "vec3", "lower corner", { unit = "m", required = true }),
      F("max", "vec3", "upper corner", { unit = "m", required = true }) } },
  { name = "HalfSpace", summary = "Points x with (x - point) . normal >= 0.", fields = {
      F("point", "vec3", "a point on the plane", { unit = "m", required = true }),
      F("normal", "vec3", "points into the half-space (any length > 0)", { required = true }) } },
  { name = "Strain", summary = "A symmetric strain tensor in the mesh frame (tensor components: xy is "
      .. "eps_xy, half the engineering shear); components left out are 0.", fields = {
      F("xx", "number", "eps_xx", { ge = -0.5, le = 0.5, default = 0, why = "a small-strain model" }),
      F("yy", "number", "eps_yy", { ge = -0.5, le = 0.5, default = 0, why = "a small-strain model" }),
      F("zz", "number", "eps_zz", { ge = -0.5, le = 0.5, default = 0, why = "a small-strain model" }),
      F("yz", "number", "eps_yz", { ge = -0.5, le = 0.5, default = 0, why = "a small-strain model" }),
      F("zx", "number", "eps_zx", { ge = -0.5, le = 0.5, default = 0, why = "a small-strain model" }),
      F("xy", "number", "eps_xy", { ge = -0.5, le = 0.5, default = 0, why = "a small-strain model" }) } },
  { name = "Render", summary = "Off-screen frames written as PNG under DIR/frames/. Without eye/target the camera "
      .. "looks at the mesh's centre from azimuth/elevation, just far enough to see all of it.", fields = {
      F("width", "integer", "image width", { unit = "px", ge = 16, le = 8192, default = 1280 }),
      F("height", "integer", "image height", { unit = "px", ge = 16, le = 8192, default = 720 }),
      F("azimuth", "number", "automatic camera: angle about `up`, counter-clockwise seen from above: with up = "
        .. "{0, 0, 1}, 0 puts the camera on the +x side of the centre looking toward -x, 90 on the +y side (for another "
        .. "`up`, 0 is the side of the world axis least aligned with it, x before y before z on ties)",
        { unit = "deg", default = -60 }),
      F("elevation", "number", "automatic camera: angle above the horizontal (90 would look along `up`)",
        { unit = "deg", gt = -90, lt = 90, default = 25,
          why = "at +-90 the camera looks along `up`; to look straight down use 89.9" }),
      F("orbit", "number", "automatic camera: azimuth rate (turntable; 0: still)", { unit = "deg/s", default = 0 }),
      F("eye", "vec3", "camera position (with target: a fixed camera)", { unit = "m" }),
      F("target", "vec3", "point looked at", { unit = "m" }),
      F("up", "vec3", "camera up direction", { default = { 0, 0, 1 } }),
      F("fov", "number", "vertical field of view", { unit = "deg", gt = 1, lt = 179, default = 30 }),
      F("every", "integer", "render every n-th frame", { ge = 1, default = 1 }),
      F("contact_sheet", "boolean", "also write contact_sheet.png, a grid of up to ~24 frames", { default = true }),
      F("msaa", "integer", "multisampling samples (0: off)", { ge = 0, le = 16, default = 4 }),
      F("wireframe", "boolean", "draw tet edges", { default = false }),
      F("show_interface", "boolean", "draw the interface nodes (the border of the operational region)", { default = false }),
      F("show_forces", "boolean", "draw the nodes tools act on and their force lines (default: with style debug)"),
      F("show_loads", "boolean", "draw each acting load (s:load) as an arrow along its total force ending at its "
        .. "nodes' centroid, the largest a tenth of the model's size (default: with style debug)"),
      F("background", "vec3", "RGB in [0, 1]", { default = { 0.2, 0.22, 0.26 } }),
      F("style", "string", "clinical: tissue coloured by material (s:material call order, or its color), "
        .. "instruments as instruments; paper: the paper's colours (operational light grey, nonoperational dark "
        .. "blue); debug: clinical plus the nodes tools act on, force lines and load arrows",
        { values = { "clinical", "paper", "debug" }, default = "clinical" }),
      F("tissue_colors", "vec3[]", "clinical style: RGB in [0, 1] per material in s:material call order, cycled "
        .. "(default: parenchyma red-brown, a pale lesion tone, ...); a material's own color wins"),
      F("cut_color", "vec3", "RGB in [0, 1] of cut faces (clinical: a cut face is its tissue's colour tinted 40 % "
        .. "toward it, so the cut shows what it exposed)", { default = { 0.72, 0.16, 0.24 } }),
      F("show_inclusions", "boolean", "clinical style: boundaries between materials inside the organ (a lesion) "
        .. "drawn faintly through the surface, as if seen under the capsule", { default = true }),
      F("depth", "boolean", "also frames/depth_NNNNNN.png: 16-bit distance along the view axis, mm x 10 "
        .. "(0: background), and camera.json (docs/rendering.md)", { default = false }),
      F("labels", "boolean", "also frames/labels_NNNNNN.png: 8-bit id per pixel (background, each material, the "
        .. "cut surface, each tool; legend in camera.json)", { default = false }),
      F("record", "boolean", "write render_record.bin for `softcut render` (default: when it stays under 256 MiB)") } },
}

api.functions = {
  { name = "softcut.params", summary = "Declares the scenario's parameters with their defaults; "
      .. "`softcut run --set key=value` overrides them (the value is converted to the default's type). "
      .. "Returns the table of effective values. Names: at most 64 letters, digits, `_`, `.` or `-`, "
      .. "starting with a letter or `_`; at most 1000 parameters. summary.json lists them, "
      .. "values shown printable and cut at 2000 bytes.", free_fields = "number, boolean or string defaults",
    returns = "table", fields = {},
    example = 'local P = softcut.params{ force = 0.8, depth = 0.004, label = "poke" }' },
  { name = "softcut.scenario", summary = "Starts a scenario: its name, timeline and reference tolerance. "
      .. "The script returns the Scenario (or the last one created is used).", returns = "Scenario", fields = {
      F("name", "string", "output folder name renders/<name>/ (default: the file name without .lua)"),
      F("duration", "number", "simulated time; frames at t = 0, 1/fps, ..., duration", { unit = "s", ge = 0, required = true }),
      F("fps", "number", "frame rate; frames are 1/fps apart", { unit = "Hz", ge = 0.001, le = 10000, default = 30,
        why = "a frame at most every 1000 s, at least every 0.1 ms; at most 10000000 frames in all" }),
      F("tolerance", "number", "`softcut check`: max |u - u_ref| allowed, relative to max |u_ref| of the reference log",
        { gt = 0, lt = 1, default = 1e-6 }),
      F("description", "string", "one line, recorded in summary.json (`scenario.description`)"),
      F("gravity", "vec3", "acceleration of gravity: a body force density x gravity on every tet (a dead "
        .. "load; the condensed region takes it through its precomputed constant term)", { unit = "m/s^2", default = { 0, 0, 0 } }) },
    example = 'local s = softcut.scenario{ name = "liver_retraction", duration = 2.0, fps = 30, gravity = {0, 0, -9.81} }' },

  { name = "Scenario:mesh", summary = "Loads or generates the rest mesh (call first). Returns a Mesh "
      .. "table: num_nodes, num_tets, labels (sorted list), min, max, center, size (m), sets (names of the "
      .. "mesh's node sets), surface_nodes (sorted 0-based ids).",
    returns = "Mesh", one_of = { { "file", "generate" } }, fields = {
      F("file", "string", "mesh file relative to the scenario (.msh, .node/.ele, .mesh, .vtk, .vtu)"),
      F("unit", "string", "length unit of `file`, default m (mesh files carry none; most CT and Gmsh exports are in mm)",
        { values = { "m", "cm", "mm", "um" } }),
      F("scale", "number", "every length of `file` times this (after `unit`), default 1", { gt = 0 }),
      F("generate", "string", "generator name: structured (box .. upper_leg), an organ shape meshed by CGAL "
        .. "(liver, kidney, knee_ligament), or `surface`: closed surfaces (STL, OBJ, PLY, OFF) meshed by CGAL "
        .. "(docs/meshing.md)",
        { values = { "box", "cylinder", "tube", "band", "ligament", "upper_leg", "liver", "kidney", "knee_ligament",
                     "surface" } }),
      F("options", "table", "generator options by name: numbers, or 3-vectors for corners/centers; cell counts "
        .. "or target counts given replace a preset's (ligament, upper_leg) resolution. `surface` takes `file` "
        .. "(a name or a list: the organ, then inner regions, labels 1, 2, ...) and `unit` (m, cm, mm, um; "
        .. "default: guessed from the size, with a warning) beside the organ kinds' sizing options. "
        .. "`softcut mesh generate` takes the same names (docs/meshing.md)") },
    example = 's:mesh{ generate = "box", options = { min = {0, 0, 0}, max = {0.1, 0.04, 0.04}, nx = 10, ny = 4, nz = 4 } }' },
  { name = "Scenario:material", summary = "Assigns a material to a set of tets (all tets when no region "
      .. "field is given); later calls override earlier ones. Give a tissue preset, E and nu, or both "
      .. "(explicit values override the preset's).", at_most_one_of = { { "label", "sphere", "box", "halfspace", "tets" } },
    fields = with(region_fields,
      F("name", "string", "for messages"),
      F("tissue", "string", "preset name from softcut.tissues"),
      F("young", "number", "Young's modulus E", { unit = "Pa", gt = 0, why = "E must be positive" }),
      F("poisson", "number", "Poisson's ratio nu", { gt = -1, lt = 0.5,
        why = "nu -> 0.5 is incompressible, which linear tets cannot represent" }),
      F("model", "string", "the law: linear (the paper's small-strain elasticity), corotational (linear "
        .. "elasticity in each tet's rotated frame: exact under large rotations, moderate strains), neohookean "
        .. "(compressible neo-Hooke as CalculiX's NEO HOOKE, for large stretch). Nonlinear laws act in the "
        .. "operational region (the condensed region is linear) or, with s:solver{ whole_body = true }, everywhere; "
        .. "docs/fidelity.md", { values = { "linear", "corotational", "neohookean" }, default = "linear" }),
      F("density", "number", "mass density, for gravity (default: the preset's, else 1000)",
        { unit = "kg/m^3", gt = 0, le = 1e5 }),
      F("color", "vec3", "rendered colour, RGB in [0, 1] (default: the palette's colour of this call's place in "
        .. "s:material call order)")),
    example = 's:material{ label = 2, tissue = "liver" }\ns:material{ sphere = { center = {0, 0, 0}, radius = 0.01 }, young = 2e4, poisson = 0.45 }\ns:material{ tissue = "liver", model = "corotational" }' },
  { name = "Scenario:prestress", summary = "Gives a set of tets an initial strain eps0 (paper Sec. 5; all tets "
      .. "when no region field is given); later calls override earlier ones on shared tets. The stress is "
      .. "D (eps - eps0): tissue held in place with eps0 < 0 is under tension, as skin and capsules are, so an "
      .. "incision through it gapes. Tets split by a cut keep their parent's eps0.",
    at_most_one_of = { { "label", "sphere", "box", "halfspace", "tets" } }, one_of = { { "strain", "tensor" } },
    fields = with(region_fields,
      F("name", "string", "for messages"),
      F("strain", "number", "isotropic initial strain (eps0 = strain I); negative: the tissue would shrink if "
        .. "freed, so held in place it is under tension", { ge = -0.5, le = 0.5, why = "a small-strain model" }),
      F("tensor", "Strain", "anisotropic initial strain, e.g. tension along one fibre direction")),
    example = 's:prestress{ label = 1, strain = -0.04 }\ns:prestress{ box = { min = {0, 0, 0}, max = {0.1, 0.1, 0.005} }, tensor = { xx = -0.05, yy = -0.02 } }' },
  { name = "Scenario:operational", summary = "Chooses the operational region (the part that can be cut and "
      .. "is solved every frame by CG; the rest is condensed). Default: none (everything condensed).",
    one_of = { { "label", "sphere", "box", "halfspace", "tets" } }, fields = region_fields,
    example = 's:operational{ sphere = { center = {0.05, 0.02, 0.04}, radius = 0.015 } }' },
  { name = "Scenario:fix", summary = "Fixes nodes: at rest (zero displacement), or moved by a prescribed "
      .. "displacement, constant or along a path over time (a patch lifted by 20 mm, a retractor's edge). "
      .. "Several calls add up; a node follows one motion. With the hybrid model a moved node must lie in "
      .. "the operational region (the condensed region is precomputed with its fixed nodes at rest).",
    at_most_one_of = { { "displacement", "path" } },
    fields = { F("nodes", "Selection", "nodes to fix", { required = true }),
      F("displacement", "vec3", "a constant prescribed displacement", { unit = "m" }),
      F("path", "Path", "the prescribed displacement over time (e.g. softcut.path.polyline from {0, 0, 0})", { unit = "m" }),
      F("name", "string", "for messages (default: motion1, motion2, ...)") },
    example = 's:fix{ nodes = softcut.select.halfspace{ point = {0, 0, 0}, normal = {-1, 0, 0} } }\n'
      .. 's:fix{ nodes = patch, path = softcut.path.polyline{ times = {0, 1}, points = {{0, 0, 0}, {0, 0, 0.02}} } }' },
  { name = "Scenario:load", summary = "A nodal force: `force` is a world vector (its length is the "
      .. "magnitude), or `normal` a magnitude along each node's outward surface normal (negative pushes in); "
      .. "both multiplied by `ramp(t)`. The total is split evenly over the nodes unless per_node is true.",
    one_of = { { "force", "normal" } }, fields = {
      F("name", "string", "for messages, outputs and Frame:set_load (default load1, load2, ...)"),
      F("nodes", "Selection", "loaded nodes (surface or operational; not interior nonoperational)", { required = true }),
      F("force", "vec3", "total force vector", { unit = "N" }),
      F("normal", "number", "total force along the outward normal", { unit = "N" }),
      F("ramp", "Ramp", "dimensionless time profile multiplying the force", { default = 1 }),
      F("per_node", "boolean", "every node gets the full force", { default = false }) },
    example = 's:load{ name = "press", nodes = softcut.select.sphere{ center = {0.05, 0.02, 0.04}, radius = 0.006 },\n        normal = -0.5, ramp = softcut.ramp.smoothstep{ t0 = 0, t1 = 1 } }' },
  { name = "Scenario:probe", summary = "A probe: a sphere tip on a path that pokes the surface it touches, "
      .. "with a ramp-driven force (`force`, spread over the circle the sphere presses into the surface; "
      .. "it acts only while the sphere reaches the surface, so let the path follow the dent) or a spring of "
      .. "total `stiffness` pushing the contact nodes to the tip's surface.", one_of = { { "force", "stiffness" } },
    ordered = { { "start", "stop", strict = true } }, fields = {
      F("name", "string", "for messages, outputs and Frame methods", { required = true }),
      F("path", "Path", "tip center over time", { required = true }),
      F("radius", "number", "tip radius", { unit = "m", gt = 0, default = 0.005 }),
      F("force", "Ramp", "force magnitude over time (drive force)", { unit = "N" }),
      F("direction", "vec3", "force direction (default: into the surface)"),
      F("stiffness", "number", "total spring stiffness (drive spring)", { unit = "N/m", gt = 0 }),
      F("start", "number", "in contact from this time", { unit = "s", ge = 0, default = 0 }),
      F("stop", "number", "until this time (default: the end)", { unit = "s", ge = 0 }),
      F("shaft", "vec3", "drawing only: direction from the tip to the handle (default: against `direction`, else "
        .. "back along the way the tip came to its first contact, else the camera's up)", { nonzero = true }) },
    example = 's:probe{ name = "tip", path = softcut.path.polyline{ times = {0, 1}, points = {{0.05, 0.02, 0.05}, {0.05, 0.02, 0.04}} },\n         radius = 0.004, stiffness = 200 }' },
  { name = "Scenario:grasper", summary = "A grasper: closes at `start` (or the first frame after it that touches) "
      .. "on the patch of surface under its jaw (facing it, within the jaw radius), points spread over it and bound to their "
      .. "triangles' nodes (so no single node is pulled into a spike), drags them along its path with a spring "
      .. "of total `stiffness` (or a force toward the tip), opens at `stop`.",
    one_of = { { "force", "stiffness" } }, ordered = { { "start", "stop", strict = true } }, fields = {
      F("name", "string", "for messages, outputs and Frame methods", { required = true }),
      F("path", "Path", "tip center over time", { required = true }),
      F("radius", "number", "jaw radius: the surface within it is grasped", { unit = "m", gt = 0, default = 0.005 }),
      F("force", "Ramp", "pull magnitude over time (drive force)", { unit = "N" }),
      F("direction", "vec3", "pull direction (default: toward the tip)"),
      F("stiffness", "number", "total spring stiffness (drive spring)", { unit = "N/m", gt = 0 }),
      F("start", "number", "closes at the first frame from this time that touches", { unit = "s", ge = 0, default = 0 }),
      F("stop", "number", "opens at this time (default: never)", { unit = "s", ge = 0 }),
      F("implicit", "boolean", "spring solved exactly within each frame (false: explicit, lags a frame and "
        .. "needs stiffness x compliance < 1)", { default = true }),
      F("shaft", "vec3", "drawing only: direction from the jaws to the handle (default: back along the way the "
        .. "jaws came to the tissue, else the camera's up)", { nonzero = true }) },
    example = 's:grasper{ name = "jaw", path = softcut.path.catmull_rom{ times = {0, 1, 2}, points = {{0, 0, 0.03}, {0, 0, 0.045}, {0.01, 0, 0.05}} },\n           stiffness = 400 }' },
  { name = "Scenario:scalpel", summary = "A scalpel: a blade edge of `length` along `axis`, centred on its path, "
      .. "that presses the surface within `radius` of the edge like a probe (`force` ramp or spring `stiffness`). "
      .. "Contact pressure = |contact force| / (length x 2 radius). From the frame it reaches `cut_pressure` the "
      .. "tissue yields (no force) and the surface the edge sweeps between frames is cut, in the operational region "
      .. "only, from where the blade entered the tissue; a cut reaching the interface stops there with a warning. "
      .. "Start the path above the surface: a blade inside the tissue that is not cutting is an error. "
      .. "See docs/outputs.md (Cutting).",
    one_of = { { "force", "stiffness" } }, ordered = { { "start", "stop", strict = true } }, fields = {
      F("name", "string", "for messages, outputs and Frame methods", { required = true }),
      F("path", "Path", "centre of the blade edge over time", { required = true }),
      F("length", "number", "blade edge length", { unit = "m", gt = 0, default = 0.02 }),
      F("axis", "vec3", "direction of the blade edge (any length > 0)", { default = { 0, 1, 0 } }),
      F("radius", "number", "contact radius around the edge (contact width = 2 radius)", { unit = "m", gt = 0, default = 0.001 }),
      F("cut_pressure", "number", "contact pressure at which the blade cuts", { unit = "Pa", gt = 0, required = true }),
      F("back", "vec3", "triangular blade: offset from the edge's centre to its third corner (default: the edge "
        .. "alone); the whole triangle sweeps, so a stab or a slice along its plane cuts its area", { unit = "m" }),
      F("force", "Ramp", "pressing force magnitude over time (drive force)", { unit = "N" }),
      F("direction", "vec3", "force direction (default: into the surface)"),
      F("stiffness", "number", "total spring stiffness (drive spring)", { unit = "N/m", gt = 0 }),
      F("start", "number", "in contact from this time", { unit = "s", ge = 0, default = 0 }),
      F("stop", "number", "until this time (default: the end)", { unit = "s", ge = 0 }),
      F("shaft", "vec3", "drawing only: direction from the edge to the handle (default: against `direction`, "
        .. "else back along the way the blade came to the tissue, else the camera's up)", { nonzero = true }) },
    example = 's:scalpel{ name = "blade", path = softcut.path.polyline{ times = {0, 1}, points = {{0.05, 0.02, 0.045}, {0.05, 0.02, 0.02}} },\n          length = 0.05, axis = {0, 1, 0}, force = softcut.ramp.linear{ t1 = 0.3, to = 2 }, cut_pressure = 2e4 }' },
  { name = "Scenario:cutting", summary = "Cutter options (rarely needed; docs/cutting.md).", fields = {
      F("snap_fraction", "number", "crossings closer than this fraction of an edge to its end snap to the node",
        { gt = 0, lt = 0.5, default = 0.15 }),
      F("min_dihedral", "number", "smallest dihedral angle of tets made by cutting", { unit = "deg", ge = 0, lt = 60, default = 10 }) },
    example = 's:cutting{ min_dihedral = 12 }' },
  { name = "Scenario:output", summary = "What the run writes besides summary.json: logged nodes in "
      .. "displacements.csv, ParaView VTU/PVD, rendered frames.", fields = {
      F("log", "Selection", "nodes written to displacements.csv (default: the whole surface)"),
      F("csv", "boolean", "write displacements.csv", { default = true }),
      F("vtu", "boolean", "write vtu/frame_NNNNNN.vtu and series.pvd", { default = false }),
      F("vtu_every", "integer", "VTU every n-th frame", { ge = 1, default = 1 }),
      F("render", "Render", "render frames off-screen (camera, size)"),
      F("video", "boolean", "also video.mp4 of the frames (H.264 at fps / render.every, through the ffmpeg program); "
        .. "turns rendering on", { default = false }) },
    example = 's:output{ log = softcut.select.surface(), vtu = true, render = { width = 640, height = 480 } }' },
  { name = "Scenario:camera", summary = "A camera that moves (instead of render's fixed or orbiting one): on a "
      .. "path looking at a point or along another path, or following a tool like an endoscope on its port: "
      .. "`distance` behind its tip along its shaft, `offset` off the shaft toward `up`, looking at the tip.",
    one_of = { { "path", "follow" } }, fields = {
      F("path", "Path", "eye position over time", { unit = "m" }),
      F("target", "Path", "point looked at (a point or a path; with `path`)", { unit = "m" }),
      F("follow", "string", "name of a tool defined before (its shaft: the tool's `shaft`, else its approach)"),
      F("distance", "number", "follow: eye behind the tip along the shaft", { unit = "m", gt = 0, default = 0.06 }),
      F("offset", "number", "follow: eye off the shaft's axis toward `up`", { unit = "m", ge = 0, default = 0.01 }),
      F("lead", "number", "follow: look this far beyond the tip", { unit = "m", default = 0 }),
      F("up", "vec3", "camera up direction", { default = { 0, 0, 1 } }),
      F("fov", "number", "vertical field of view (default: render's)", { unit = "deg", gt = 1, lt = 179 }) },
    example = 's:camera{ path = softcut.path.polyline{ times = {0, 2}, points = {{0.2, -0.2, 0.15}, {0.1, -0.25, 0.1}} },\n          target = {0.05, 0.02, 0.03} }\ns:camera{ follow = "jaw", distance = 0.05, fov = 60 }' },
  { name = "Scenario:solver", summary = "Solver knobs (rarely needed).", fields = {
      F("tolerance", "number", "relative CG residual", { gt = 0, lt = 1, default = 1e-10 }),
      F("max_iterations", "integer", "CG iteration cap (0: automatic)", { ge = 0, default = 0 }),
      F("backend", "string", "operational solver: auto (direct: the fastest exact solver measured), cpu (the paper's "
        .. "CG), gpu (CG in compute shaders, also on llvmpipe), direct (CHOLMOD, factor kept between frames), "
        .. "monolithic (whole mesh, no condensation: a reference). A nonlinear frame (a nonlinear law, a prescribed "
        .. "motion) is solved by Newton on every backend: its steps' PCG is preconditioned by the kept factor "
        .. "(direct, monolithic) or by block Jacobi on the CPU (cpu, gpu)",
        { values = { "auto", "cpu", "gpu", "direct", "monolithic" }, default = "auto" }),
      F("gpu_fp64", "boolean", "gpu: fp64 kernels instead of fp32 with fp64 refinement", { default = false }),
      F("mode", "string", "nonoperational data: auto (product or factor, by memory and cost), dense (the paper's "
        .. "blocks, O(surface^2) memory), product (K*^-1 P* dense, columns of loaded nodes on demand), factor "
        .. "(a K22 solve per full-surface frame)", { values = { "auto", "dense", "product", "factor" }, default = "auto" }),
      F("newton_tolerance", "number", "nonlinear frames: Newton's relative residual", { gt = 0, lt = 1e-2, default = 1e-10 }),
      F("newton_max_iterations", "integer", "nonlinear frames: Newton steps before the frame is an error",
        { ge = 1, le = 1000, default = 40 }),
      F("whole_body", "boolean", "every tet by its material's law and nothing condensed: the fully nonlinear answer "
        .. "for bodies small enough to solve whole (backend auto or monolithic)", { default = false }) },
    example = 's:solver{ backend = "cpu" }\ns:solver{ whole_body = true }' },
  { name = "Scenario:expect", summary = "A check for `softcut check` (also reported by `softcut run`): "
      .. "bounds on the displacement of a node set at time `at` (the first frame at or after it), or a "
      .. "function(frame) returning true, or false and a message. Failures point at this line.",
    one_of = { { "nodes", "check" } }, ordered = { { "min", "max" } }, fields = {
      F("name", "string", "for messages"),
      F("at", "number", "time of the check", { unit = "s", ge = 0, required = true }),
      F("nodes", "Selection", "node set measured"),
      F("measure", "string", "mean: of the mean displacement vector; max: over the nodes, the largest magnitude, or for x/y/z the component largest in absolute value (signed)",
        { values = { "mean", "max" }, default = "mean" }),
      F("component", "string", "which part of the displacement", { values = { "magnitude", "x", "y", "z" }, default = "magnitude" }),
      F("min", "number", "lower bound", { unit = "m" }),
      F("max", "number", "upper bound", { unit = "m" }),
      F("check", "function", "function(frame) -> ok [, message]"),
      F("message", "string", "shown when `check` fails") },
    example = 's:expect{ at = 1.0, nodes = tip_nodes, component = "z", min = -0.006, max = -0.002 }\ns:expect{ at = 2.0, check = function(f) return f:tool("jaw").engaged end, message = "grasper let go" }' },
  { name = "Scenario:on_frame", summary = "Calls fn(frame) after every frame: read displacements, move "
      .. "tools, change loads, stop the run. Errors end the run (outputs are kept, summary marks the error).",
    positional = { F("fn", "function", "function(frame)", { required = true }) }, fields = {},
    example = 's:on_frame(function(f)\n  if f:max_displacement(tip) > 0.01 then f:stop() end\nend)' },
  { name = "Scenario:select", summary = "Evaluates a selection on the mesh now: sorted 0-based node ids "
      .. "(an error at this line when empty).", positional = { F("sel", "Selection", "selection", { required = true }) },
    fields = {}, returns = "integer[]", example = 'local ids = s:select(softcut.select.label(2))' },

  { name = "softcut.select.all", summary = "Every node used by a tet.", positional = {}, fields = {}, returns = "Selection",
    example = "softcut.select.all()" },
  { name = "softcut.select.label", summary = "Nodes of the tets with a label.",
    positional = { F("label", "integer", "mesh label", { required = true }) }, fields = {}, returns = "Selection",
    example = "softcut.select.label(2)" },
  { name = "softcut.select.surface", summary = "Boundary nodes of the whole body, or of the tets with `label`.",
    positional = { F("label", "integer", "mesh label (default: whole body)") }, fields = {}, returns = "Selection",
    example = "softcut.select.surface()" },
  { name = "softcut.select.sphere", summary = "Nodes within a ball.", fields = api.structs[1].fields,
    returns = "Selection", example = "softcut.select.sphere{ center = {0, 0, 0.03}, radius = 0.005 }" },
  { name = "softcut.select.box", summary = "Nodes in an axis-aligned box (inclusive).", fields = api.structs[2].fields,
    returns = "Selection", example = "softcut.select.box{ min = {0, 0, 0}, max = {0.001, 0.04, 0.04} }" },
  { name = "softcut.select.halfspace", summary = "Nodes with (x - point) . normal >= 0.", fields = api.structs[3].fields,
    returns = "Selection", example = "softcut.select.halfspace{ point = {0, 0, 0}, normal = {-1, 0, 0} }" },
  { name = "softcut.select.nodes", summary = "Explicit 0-based node ids (as in the mesh file and the CSV).",
    positional = { F("ids", "integer[]", "node ids", { required = true, ge = 0 }) }, fields = {}, returns = "Selection",
    example = "softcut.select.nodes{ 0, 5, 17 }" },
  { name = "softcut.select.named", summary = "A node set the mesh provides: \"hole\" of the tube / upper_leg "
      .. "generator; a generated organ's landmarks (liver: right_lobe, left_lobe, underside, dome, lesion; kidney: "
      .. "hilum, convex, upper_pole, lower_pole, underside, top; knee_ligament: tibial, femoral; docs/meshing.md).",
    positional = { F("name", "string", "set name", { required = true }) }, fields = {}, returns = "Selection",
    example = 'softcut.select.named("hole")' },
  { name = "Selection:union", summary = "Nodes in either (also `a + b`).",
    positional = { F("other", "Selection", "other set", { required = true }) }, fields = {}, returns = "Selection",
    example = "a + b" },
  { name = "Selection:intersection", summary = "Nodes in both (also `a * b`).",
    positional = { F("other", "Selection", "other set", { required = true }) }, fields = {}, returns = "Selection",
    example = "softcut.select.surface() * softcut.select.label(2)" },
  { name = "Selection:difference", summary = "Nodes in this set and not the other (also `a - b`).",
    positional = { F("other", "Selection", "other set", { required = true }) }, fields = {}, returns = "Selection",
    example = "softcut.select.all() - softcut.select.named(\"hole\")" },

  { name = "softcut.ramp.constant", summary = "The same value at every time.",
    positional = { F("value", "number", "value", { required = true }) }, fields = {}, returns = "Ramp",
    example = "softcut.ramp.constant(0.5)" },
  { name = "softcut.ramp.linear", summary = "`from` until t0, straight line to `to` at t1, then `to`.", fields = {
      F("t0", "number", "start", { unit = "s", default = 0 }),
      F("t1", "number", "end (> t0)", { unit = "s", required = true }),
      F("from", "number", "value before t0", { default = 0 }),
      F("to", "number", "value from t1 on", { default = 1 }) }, returns = "Ramp",
    example = "softcut.ramp.linear{ t0 = 0, t1 = 1 }" },
  { name = "softcut.ramp.smoothstep", summary = "Like linear, with zero slope at both ends (3s^2 - 2s^3).", fields = {
      F("t0", "number", "start", { unit = "s", default = 0 }),
      F("t1", "number", "end (> t0)", { unit = "s", required = true }),
      F("from", "number", "value before t0", { default = 0 }),
      F("to", "number", "value from t1 on", { default = 1 }) }, returns = "Ramp",
    example = "softcut.ramp.smoothstep{ t0 = 0.2, t1 = 1.2, to = 1 }" },
  { name = "softcut.ramp.keyframes", summary = "Piecewise linear through (times[k], values[k]); held before the first and after the last key.",
    fields = {
      F("times", "number[]", "key times, strictly increasing", { unit = "s", required = true }),
      F("values", "number[]", "key values, as many as times", { required = true }) }, returns = "Ramp",
    example = "softcut.ramp.keyframes{ times = {0, 0.5, 1.5, 2}, values = {0, 1, 1, 0} }" },
  { name = "softcut.ramp.sine", summary = "offset + amplitude * sin(2 pi frequency (t - t0) + phase) from t0; offset before.", fields = {
      F("amplitude", "number", "amplitude", { required = true }),
      F("frequency", "number", "frequency", { unit = "Hz", ge = 0, required = true }),
      F("phase", "number", "phase", { unit = "rad", default = 0 }),
      F("offset", "number", "mean value", { default = 0 }),
      F("t0", "number", "start", { unit = "s", default = 0 }) }, returns = "Ramp",
    example = "softcut.ramp.sine{ amplitude = 0.5, offset = 0.5, frequency = 2 }" },
  { name = "Ramp:at", summary = "Value at time t (the engine's evaluation).",
    positional = { F("t", "number", "time", { unit = "s", required = true }) }, fields = {}, returns = "number",
    example = "softcut.ramp.linear{ t1 = 2 }:at(1) --> 0.5" },

  { name = "softcut.path.fixed", summary = "A tool that stays at one point.",
    positional = { F("point", "vec3", "position", { unit = "m", required = true }) }, fields = {}, returns = "Path",
    example = "softcut.path.fixed{ 0, 0, 0.05 }" },
  { name = "softcut.path.polyline", summary = "Straight segments between keyed points, constant speed on each; held before the first and after the last key.",
    fields = {
      F("times", "number[]", "key times, strictly increasing", { unit = "s", required = true }),
      F("points", "vec3[]", "key points, as many as times", { unit = "m", required = true }) }, returns = "Path",
    example = "softcut.path.polyline{ times = {0, 1, 2}, points = {{0, 0, 0.05}, {0, 0, 0.04}, {0.01, 0, 0.04}} }" },
  { name = "softcut.path.catmull_rom", summary = "A C1 curve through every keyed point at its time.", fields = {
      F("times", "number[]", "key times, strictly increasing", { unit = "s", required = true }),
      F("points", "vec3[]", "key points, as many as times", { unit = "m", required = true }) }, returns = "Path",
    example = "softcut.path.catmull_rom{ times = {0, 1, 2}, points = {{0, 0, 0.05}, {0.01, 0, 0.045}, {0.02, 0, 0.05}} }" },
  { name = "softcut.path.arc", summary = "`start` rotated about the axis through `center` by an angle growing linearly from 0 at t0 to `sweep` at t1.",
    fields = {
      F("center", "vec3", "a point on the rotation axis", { unit = "m", required = true }),
      F("axis", "vec3", "rotation axis (right-hand rule; any length > 0)", { default = { 0, 0, 1 } }),
      F("start", "vec3", "position at t0", { unit = "m", required = true }),
      F("sweep", "number", "total angle", { unit = "rad", required = true }),
      F("t0", "number", "start time", { unit = "s", default = 0 }),
      F("t1", "number", "end time (> t0)", { unit = "s", required = true }) }, returns = "Path",
    example = "softcut.path.arc{ center = {0, 0, 0}, start = {0.03, 0, 0.02}, sweep = math.pi / 2, t1 = 2 }" },
  { name = "Path:at", summary = "Position at time t (the engine's evaluation).",
    positional = { F("t", "number", "time", { unit = "s", required = true }) }, fields = {}, returns = "vec3",
    example = "local p = path:at(0.5)" },

  { name = "softcut.vec.add", summary = "a + b.", positional = { F("a", "vec3", "", { required = true }), F("b", "vec3", "", { required = true }) },
    fields = {}, returns = "vec3", example = "softcut.vec.add({1, 0, 0}, {0, 1, 0})" },
  { name = "softcut.vec.sub", summary = "a - b.", positional = { F("a", "vec3", "", { required = true }), F("b", "vec3", "", { required = true }) },
    fields = {}, returns = "vec3", example = "softcut.vec.sub(m.max, m.min)" },
  { name = "softcut.vec.scale", summary = "k a.", positional = { F("a", "vec3", "", { required = true }), F("k", "number", "", { required = true }) },
    fields = {}, returns = "vec3", example = "softcut.vec.scale({1, 2, 3}, 0.5)" },
  { name = "softcut.vec.dot", summary = "a . b.", positional = { F("a", "vec3", "", { required = true }), F("b", "vec3", "", { required = true }) },
    fields = {}, returns = "number", example = "softcut.vec.dot(u, {0, 0, 1})" },
  { name = "softcut.vec.cross", summary = "a x b.", positional = { F("a", "vec3", "", { required = true }), F("b", "vec3", "", { required = true }) },
    fields = {}, returns = "vec3", example = "softcut.vec.cross({1, 0, 0}, {0, 1, 0})" },
  { name = "softcut.vec.length", summary = "|a|.", positional = { F("a", "vec3", "", { required = true }) },
    fields = {}, returns = "number", example = "softcut.vec.length(f:displacement(12))" },
  { name = "softcut.vec.lerp", summary = "a + s (b - a).", positional = { F("a", "vec3", "", { required = true }),
      F("b", "vec3", "", { required = true }), F("s", "number", "", { required = true }) },
    fields = {}, returns = "vec3", example = "softcut.vec.lerp(m.min, m.max, 0.5)" },

  { name = "Frame:displacement", summary = "Displacement of a node (0-based id) this frame; nodes made by "
      .. "cutting have ids after the rest mesh's. Nodes inside the nonoperational region are solved only when "
      .. "logged (s:output{ log = ... }), exported or under an expectation's bounds; reading one otherwise is "
      .. "an error (here and in the other Frame node reads).",
    positional = { F("node", "integer", "node id", { required = true, ge = 0 }) }, fields = {}, returns = "vec3",
    example = "local u = f:displacement(42)" },
  { name = "Frame:position", summary = "Deformed position of a node this frame.",
    positional = { F("node", "integer", "node id", { required = true, ge = 0 }) }, fields = {}, returns = "vec3",
    example = "local x = f:position(42)" },
  { name = "Frame:mean_displacement", summary = "Mean displacement vector of a node set.",
    positional = { F("nodes", "Selection", "node set", { required = true }) }, fields = {}, returns = "vec3",
    example = "local u = f:mean_displacement(tip)" },
  { name = "Frame:max_displacement", summary = "Largest displacement magnitude over a node set.",
    positional = { F("nodes", "Selection", "node set", { required = true }) }, fields = {}, returns = "number",
    example = "if f:max_displacement(softcut.select.surface()) > 0.02 then f:stop() end" },
  { name = "Frame:tool", summary = "A tool's state: tip (vec3, m), engaged (boolean), num_nodes (the nodes it acts "
      .. "on: a grip's are its triangles' corners), force (vec3 {x, y, z}, N: the total force the tool applies to the "
      .. "tissue; its magnitude is softcut.vec.length(force)), pressure (Pa: a scalpel's contact pressure, else 0) "
      .. "and cutting (a scalpel cut this frame).",
    positional = { F("name", "string", "tool name", { required = true }) }, fields = {}, returns = "table",
    example = "local jaw = f:tool(\"jaw\")\nif softcut.vec.length(jaw.force) > 2 then f:stop() end" },
  { name = "Frame:cutting", summary = "Cutting so far: events (frames in which a blade changed the mesh), "
      .. "nodes_added, nodes, tets (of the current mesh), faces_separated (faces the blades opened, all events), "
      .. "faces_pending (faces on the cut still joined now: the cut front), components (pieces joined through "
      .. "shared nodes), pieces (rigid pieces: joined through shared faces, so a piece hanging by an edge counts "
      .. "apart), detached (pieces cut free and held). A cut through the section shows as components > 1.",
    positional = {}, fields = {}, returns = "table",
    example = "if f:cutting().components == 2 then f:stop() end" },
  { name = "Frame:move_tool", summary = "Places a tool's tip for the next frames (overrides its path); nil returns it to the path.",
    positional = { F("name", "string", "tool name", { required = true }), F("point", "vec3", "tip position", { unit = "m" }) },
    fields = {}, example = "f:move_tool(\"tip\", { 0.05, 0.02, 0.045 })" },
  { name = "Frame:enable_tool", summary = "Switches a tool on or off (a grasper lets go when off).",
    positional = { F("name", "string", "tool name", { required = true }), F("on", "boolean", "on", { required = true }) },
    fields = {}, example = "f:enable_tool(\"jaw\", false)" },
  { name = "Frame:set_load", summary = "Changes a load from the next frame: scale multiplies its ramp, enabled switches it.",
    positional = { F("name", "string", "load name", { required = true }) }, fields = {
      F("scale", "number", "multiplies the load's force"),
      F("enabled", "boolean", "on or off") },
    example = "f:set_load(\"press\", { scale = 2 })" },
  { name = "Frame:stop", summary = "Ends the run after this frame (summary: stopped).", positional = {}, fields = {},
    example = "f:stop()" },
  { name = "Frame:record", summary = "Records a named number this frame (a jaw's force, a gap, a volume): "
      .. "summary.json `metrics` keeps its last value (and frame, time), min, max, mean and samples; softcut sweep "
      .. "gives it the column metric.<name> (the last value). Call it every frame or once at the end; a run records "
      .. "at most 256 names.",
    positional = { F("name", "string", "1 to 64 letters, digits, _ . or -, starting with a letter or _",
                     { required = true }),
                   F("value", "number", "a finite number, in the unit the name says", { required = true }) },
    fields = {},
    example = "f:record(\"jaw_force\", softcut.vec.length(f:tool(\"jaw\").force))" },
}

-- Lookup by qualified name, with the short name used in messages
-- ("Scenario:material" -> "material", "softcut.select.box" -> "select.box").
api.by_name = {}
for i, list in ipairs({ api.functions, api.structs }) do
  for _, f in ipairs(list) do
    f.is_struct = (i == 2)
    f.short = f.name:gsub("^softcut%.", ""):gsub("^%u%w*:", "")
    api.by_name[f.name] = f
  end
end

-- Fields of the Frame an on_frame or check function receives (read-only).
api.frame_fields = {
  F("frame", "integer", "frame index: 0 at t = 0, then 1, 2, ..."),
  F("time", "number", "simulated time of this frame (frame / fps)", { unit = "s" }),
}

-- Values (not functions) of the library, documented too.
api.values = {
  { name = "softcut.tissues", summary = "Tissue presets: name -> { young = Pa, poisson, source }. "
      .. "Plausible linear stand-ins; values vary 2-10x between studies." },
  { name = "softcut.version", summary = "Engine version string." },
}

return api
