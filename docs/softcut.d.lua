---@meta softcut
-- Generated from lua/api.lua by scripts/lua_api_docs.lua; do not edit.
-- Editor annotations (lua-language-server) for softcut scenarios.

---@class Scenario
local Scenario = {}

---@class Selection
local Selection = {}

---@class Ramp
local Ramp = {}

---@class Path
local Path = {}

---@class Frame
local Frame = {}

---@class Mesh
---@field num_nodes integer
---@field num_tets integer
---@field labels integer[]
---@field min number[]
---@field max number[]
---@field center number[]
---@field size number[]
---@field sets string[]
---@field surface_nodes integer[]

---@class Frame
---@field frame integer frame index: 0 at t = 0, then 1, 2, ...
---@field time number simulated time of this frame (frame / fps) (s)

---@class Sphere A ball.
---@field center number[] center (m)
---@field radius number radius (m)

---@class Box An axis-aligned box, bounds inclusive.
---@field min number[] lower corner (m)
---@field max number[] upper corner (m)

---@class HalfSpace Points x with (x - point) . normal >= 0.
---@field point number[] a point on the plane (m)
---@field normal number[] points into the half-space (any length > 0)

---@class Strain A symmetric strain tensor in the mesh frame (tensor components: xy is eps_xy, half the engineering shear); components left out are 0.
---@field xx? number eps_xx
---@field yy? number eps_yy
---@field zz? number eps_zz
---@field yz? number eps_yz
---@field zx? number eps_zx
---@field xy? number eps_xy

---@class Render Off-screen frames written as PNG under DIR/frames/. Without eye/target the camera looks at the mesh's centre from azimuth/elevation, just far enough to see all of it.
---@field width? integer image width (px)
---@field height? integer image height (px)
---@field azimuth? number automatic camera: angle about `up`, counter-clockwise seen from above: with up = {0, 0, 1}, 0 puts the camera on the +x side of the centre looking toward -x, 90 on the +y side (for another `up`, 0 is the side of the world axis least aligned with it, x before y before z on ties) (deg)
---@field elevation? number automatic camera: angle above the horizontal (90 would look along `up`) (deg)
---@field orbit? number automatic camera: azimuth rate (turntable; 0: still) (deg/s)
---@field eye? number[] camera position (with target: a fixed camera) (m)
---@field target? number[] point looked at (m)
---@field up? number[] camera up direction
---@field fov? number vertical field of view (deg)
---@field every? integer render every n-th frame
---@field contact_sheet? boolean also write contact_sheet.png, a grid of up to ~24 frames
---@field msaa? integer multisampling samples (0: off)
---@field wireframe? boolean draw tet edges
---@field show_interface? boolean draw the interface nodes (the border of the operational region)
---@field show_forces? boolean draw the nodes tools act on and their force lines (default: with style debug)
---@field show_loads? boolean draw each acting load (s:load) as an arrow along its total force ending at its nodes' centroid, the largest a tenth of the model's size (default: with style debug)
---@field background? number[] RGB in [0, 1]
---@field style? string clinical: tissue coloured by material (s:material call order, or its color), instruments as instruments; paper: the paper's colours (operational light grey, nonoperational dark blue); debug: clinical plus the nodes tools act on, force lines and load arrows
---@field tissue_colors? number[][] clinical style: RGB in [0, 1] per material in s:material call order, cycled (default: parenchyma red-brown, a pale lesion tone, ...); a material's own color wins
---@field cut_color? number[] RGB in [0, 1] of cut faces (clinical: a cut face is its tissue's colour tinted 40 % toward it, so the cut shows what it exposed)
---@field show_inclusions? boolean clinical style: boundaries between materials inside the organ (a lesion) drawn faintly through the surface, as if seen under the capsule
---@field depth? boolean also frames/depth_NNNNNN.png: 16-bit distance along the view axis, mm x 10 (0: background), and camera.json (docs/rendering.md)
---@field labels? boolean also frames/labels_NNNNNN.png: 8-bit id per pixel (background, each material, the cut surface, each tool; legend in camera.json)
---@field record? boolean write render_record.bin for `softcut render` (default: when it stays under 256 MiB)

softcut = {}
softcut.select = {}
softcut.ramp = {}
softcut.path = {}
softcut.vec = {}
---@type table<string, {young: number, poisson: number, source: string}>
softcut.tissues = {}
---@type string
softcut.version = ""

---Declares the scenario's parameters with their defaults; `softcut run --set key=value` overrides them (the value is converted to the default's type). Returns the table of effective values. Names: at most 64 letters, digits, `_`, `.` or `-`, starting with a letter or `_`; at most 1000 parameters. summary.json lists them, values shown printable and cut at 2000 bytes.
---@param args table
---@return table
function softcut.params(args) end

---@class softcut_scenario_args
---@field name? string output folder name renders/<name>/ (default: the file name without .lua)
---@field duration number simulated time; frames at t = 0, 1/fps, ..., duration (s)
---@field fps? number frame rate; frames are 1/fps apart (Hz)
---@field tolerance? number `softcut check`: max |u - u_ref| allowed, relative to max |u_ref| of the reference log
---@field description? string one line, recorded in summary.json (`scenario.description`)
---@field gravity? number[] acceleration of gravity: a body force density x gravity on every tet (a dead load; the condensed region takes it through its precomputed constant term) (m/s^2)
---Starts a scenario: its name, timeline and reference tolerance. The script returns the Scenario (or the last one created is used).
---@param args softcut_scenario_args
---@return Scenario
function softcut.scenario(args) end

---@class Scenario_mesh_args
---@field file? string mesh file relative to the scenario (.msh, .node/.ele, .mesh, .vtk, .vtu)
---@field unit? string length unit of `file`, default m (mesh files carry none; most CT and Gmsh exports are in mm)
---@field scale? number every length of `file` times this (after `unit`), default 1
---@field generate? string generator name: structured (box .. upper_leg), an organ shape meshed by CGAL (liver, kidney, knee_ligament), or `surface`: closed surfaces (STL, OBJ, PLY, OFF) meshed by CGAL (docs/meshing.md)
---@field options? table generator options by name: numbers, or 3-vectors for corners/centers; cell counts or target counts given replace a preset's (ligament, upper_leg) resolution. `surface` takes `file` (a name or a list: the organ, then inner regions, labels 1, 2, ...) and `unit` (m, cm, mm, um; default: guessed from the size, with a warning) beside the organ kinds' sizing options. `softcut mesh generate` takes the same names (docs/meshing.md)
---Loads or generates the rest mesh (call first). Returns a Mesh table: num_nodes, num_tets, labels (sorted list), min, max, center, size (m), sets (names of the mesh's node sets), surface_nodes (sorted 0-based ids).
---@param args Scenario_mesh_args
---@return Mesh
function Scenario:mesh(args) end

---@class Scenario_material_args
---@field label? integer tets with this mesh label
---@field sphere? Sphere tets whose centroid lies in the sphere
---@field box? Box tets whose centroid lies in the axis-aligned box
---@field halfspace? HalfSpace tets whose centroid lies on the normal's side of the plane
---@field tets? integer[] explicit 0-based tet ids
---@field name? string for messages
---@field tissue? string preset name from softcut.tissues
---@field young? number Young's modulus E (Pa)
---@field poisson? number Poisson's ratio nu
---@field model? string the law: linear (the paper's small-strain elasticity), corotational (linear elasticity in each tet's rotated frame: exact under large rotations, moderate strains), neohookean (compressible neo-Hooke as CalculiX's NEO HOOKE, for large stretch). Nonlinear laws act in the operational region (the condensed region is linear) or, with s:solver{ whole_body = true }, everywhere; docs/fidelity.md
---@field density? number mass density, for gravity (default: the preset's, else 1000) (kg/m^3)
---@field color? number[] rendered colour, RGB in [0, 1] (default: the palette's colour of this call's place in s:material call order)
---Assigns a material to a set of tets (all tets when no region field is given); later calls override earlier ones. Give a tissue preset, E and nu, or both (explicit values override the preset's).
---@param args Scenario_material_args
function Scenario:material(args) end

---@class Scenario_prestress_args
---@field label? integer tets with this mesh label
---@field sphere? Sphere tets whose centroid lies in the sphere
---@field box? Box tets whose centroid lies in the axis-aligned box
---@field halfspace? HalfSpace tets whose centroid lies on the normal's side of the plane
---@field tets? integer[] explicit 0-based tet ids
---@field name? string for messages
---@field strain? number isotropic initial strain (eps0 = strain I); negative: the tissue would shrink if freed, so held in place it is under tension
---@field tensor? Strain anisotropic initial strain, e.g. tension along one fibre direction
---Gives a set of tets an initial strain eps0 (paper Sec. 5; all tets when no region field is given); later calls override earlier ones on shared tets. The stress is D (eps - eps0): tissue held in place with eps0 < 0 is under tension, as skin and capsules are, so an incision through it gapes. Tets split by a cut keep their parent's eps0.
---@param args Scenario_prestress_args
function Scenario:prestress(args) end

---@class Scenario_operational_args
---@field label? integer tets with this mesh label
---@field sphere? Sphere tets whose centroid lies in the sphere
---@field box? Box tets whose centroid lies in the axis-aligned box
---@field halfspace? HalfSpace tets whose centroid lies on the normal's side of the plane
---@field tets? integer[] explicit 0-based tet ids
---Chooses the operational region (the part that can be cut and is solved every frame by CG; the rest is condensed). Default: none (everything condensed).
---@param args Scenario_operational_args
function Scenario:operational(args) end

---@class Scenario_fix_args
---@field nodes Selection nodes to fix
---@field displacement? number[] a constant prescribed displacement (m)
---@field path? Path|number[] the prescribed displacement over time (e.g. softcut.path.polyline from {0, 0, 0}) (m)
---@field name? string for messages (default: motion1, motion2, ...)
---Fixes nodes: at rest (zero displacement), or moved by a prescribed displacement, constant or along a path over time (a patch lifted by 20 mm, a retractor's edge). Several calls add up; a node follows one motion. With the hybrid model a moved node must lie in the operational region (the condensed region is precomputed with its fixed nodes at rest).
---@param args Scenario_fix_args
function Scenario:fix(args) end

---@class Scenario_load_args
---@field name? string for messages, outputs and Frame:set_load (default load1, load2, ...)
---@field nodes Selection loaded nodes (surface or operational; not interior nonoperational)
---@field force? number[] total force vector (N)
---@field normal? number total force along the outward normal (N)
---@field ramp? Ramp|number dimensionless time profile multiplying the force
---@field per_node? boolean every node gets the full force
---A nodal force: `force` is a world vector (its length is the magnitude), or `normal` a magnitude along each node's outward surface normal (negative pushes in); both multiplied by `ramp(t)`. The total is split evenly over the nodes unless per_node is true.
---@param args Scenario_load_args
function Scenario:load(args) end

---@class Scenario_probe_args
---@field name string for messages, outputs and Frame methods
---@field path Path|number[] tip center over time
---@field radius? number tip radius (m)
---@field force? Ramp|number force magnitude over time (drive force) (N)
---@field direction? number[] force direction (default: into the surface)
---@field stiffness? number total spring stiffness (drive spring) (N/m)
---@field start? number in contact from this time (s)
---@field stop? number until this time (default: the end) (s)
---@field shaft? number[] drawing only: direction from the tip to the handle (default: against `direction`, else back along the way the tip came to its first contact, else the camera's up)
---A probe: a sphere tip on a path that pokes the surface it touches, with a ramp-driven force (`force`, spread over the circle the sphere presses into the surface; it acts only while the sphere reaches the surface, so let the path follow the dent) or a spring of total `stiffness` pushing the contact nodes to the tip's surface.
---@param args Scenario_probe_args
function Scenario:probe(args) end

---@class Scenario_grasper_args
---@field name string for messages, outputs and Frame methods
---@field path Path|number[] tip center over time
---@field radius? number jaw radius: the surface within it is grasped (m)
---@field force? Ramp|number pull magnitude over time (drive force) (N)
---@field direction? number[] pull direction (default: toward the tip)
---@field stiffness? number total spring stiffness (drive spring) (N/m)
---@field start? number closes at the first frame from this time that touches (s)
---@field stop? number opens at this time (default: never) (s)
---@field implicit? boolean spring solved exactly within each frame (false: explicit, lags a frame and needs stiffness x compliance < 1)
---@field shaft? number[] drawing only: direction from the jaws to the handle (default: back along the way the jaws came to the tissue, else the camera's up)
---A grasper: closes at `start` (or the first frame after it that touches) on the patch of surface under its jaw (facing it, within the jaw radius), points spread over it and bound to their triangles' nodes (so no single node is pulled into a spike), drags them along its path with a spring of total `stiffness` (or a force toward the tip), opens at `stop`.
---@param args Scenario_grasper_args
function Scenario:grasper(args) end

---@class Scenario_scalpel_args
---@field name string for messages, outputs and Frame methods
---@field path Path|number[] centre of the blade edge over time
---@field length? number blade edge length (m)
---@field axis? number[] direction of the blade edge (any length > 0)
---@field radius? number contact radius around the edge (contact width = 2 radius) (m)
---@field cut_pressure number contact pressure at which the blade cuts (Pa)
---@field back? number[] triangular blade: offset from the edge's centre to its third corner (default: the edge alone); the whole triangle sweeps, so a stab or a slice along its plane cuts its area (m)
---@field force? Ramp|number pressing force magnitude over time (drive force) (N)
---@field direction? number[] force direction (default: into the surface)
---@field stiffness? number total spring stiffness (drive spring) (N/m)
---@field start? number in contact from this time (s)
---@field stop? number until this time (default: the end) (s)
---@field shaft? number[] drawing only: direction from the edge to the handle (default: against `direction`, else back along the way the blade came to the tissue, else the camera's up)
---A scalpel: a blade edge of `length` along `axis`, centred on its path, that presses the surface within `radius` of the edge like a probe (`force` ramp or spring `stiffness`). Contact pressure = |contact force| / (length x 2 radius). From the frame it reaches `cut_pressure` the tissue yields (no force) and the surface the edge sweeps between frames is cut, in the operational region only, from where the blade entered the tissue; a cut reaching the interface stops there with a warning. Start the path above the surface: a blade inside the tissue that is not cutting is an error. See docs/outputs.md (Cutting).
---@param args Scenario_scalpel_args
function Scenario:scalpel(args) end

---@class Scenario_cutting_args
---@field snap_fraction? number crossings closer than this fraction of an edge to its end snap to the node
---@field min_dihedral? number smallest dihedral angle of tets made by cutting (deg)
---Cutter options (rarely needed; docs/cutting.md).
---@param args Scenario_cutting_args
function Scenario:cutting(args) end

---@class Scenario_output_args
---@field log? Selection nodes written to displacements.csv (default: the whole surface)
---@field csv? boolean write displacements.csv
---@field vtu? boolean write vtu/frame_NNNNNN.vtu and series.pvd
---@field vtu_every? integer VTU every n-th frame
---@field render? Render render frames off-screen (camera, size)
---@field video? boolean also video.mp4 of the frames (H.264 at fps / render.every, through the ffmpeg program); turns rendering on
---What the run writes besides summary.json: logged nodes in displacements.csv, ParaView VTU/PVD, rendered frames.
---@param args Scenario_output_args
function Scenario:output(args) end

---@class Scenario_camera_args
---@field path? Path|number[] eye position over time (m)
---@field target? Path|number[] point looked at (a point or a path; with `path`) (m)
---@field follow? string name of a tool defined before (its shaft: the tool's `shaft`, else its approach)
---@field distance? number follow: eye behind the tip along the shaft (m)
---@field offset? number follow: eye off the shaft's axis toward `up` (m)
---@field lead? number follow: look this far beyond the tip (m)
---@field up? number[] camera up direction
---@field fov? number vertical field of view (default: render's) (deg)
---A camera that moves (instead of render's fixed or orbiting one): on a path looking at a point or along another path, or following a tool like an endoscope on its port: `distance` behind its tip along its shaft, `offset` off the shaft toward `up`, looking at the tip.
---@param args Scenario_camera_args
function Scenario:camera(args) end

---@class Scenario_solver_args
---@field tolerance? number relative CG residual
---@field max_iterations? integer CG iteration cap (0: automatic)
---@field backend? string operational solver: auto (direct: the fastest exact solver measured), cpu (the paper's CG), gpu (CG in compute shaders, also on llvmpipe), direct (CHOLMOD, factor kept between frames), monolithic (whole mesh, no condensation: a reference). A nonlinear frame (a nonlinear law, a prescribed motion) is solved by Newton on every backend: its steps' PCG is preconditioned by the kept factor (direct, monolithic) or by block Jacobi on the CPU (cpu, gpu)
---@field gpu_fp64? boolean gpu: fp64 kernels instead of fp32 with fp64 refinement
---@field mode? string nonoperational data: auto (product or factor, by memory and cost), dense (the paper's blocks, O(surface^2) memory), product (K*^-1 P* dense, columns of loaded nodes on demand), factor (a K22 solve per full-surface frame)
---@field newton_tolerance? number nonlinear frames: Newton's relative residual
---@field newton_max_iterations? integer nonlinear frames: Newton steps before the frame is an error
---@field whole_body? boolean every tet by its material's law and nothing condensed: the fully nonlinear answer for bodies small enough to solve whole (backend auto or monolithic)
---Solver knobs (rarely needed).
---@param args Scenario_solver_args
function Scenario:solver(args) end

---@class Scenario_expect_args
---@field name? string for messages
---@field at number time of the check (s)
---@field nodes? Selection node set measured
---@field measure? string mean: of the mean displacement vector; max: over the nodes, the largest magnitude, or for x/y/z the component largest in absolute value (signed)
---@field component? string which part of the displacement
---@field min? number lower bound (m)
---@field max? number upper bound (m)
---@field check? function function(frame) -> ok [, message]
---@field message? string shown when `check` fails
---A check for `softcut check` (also reported by `softcut run`): bounds on the displacement of a node set at time `at` (the first frame at or after it), or a function(frame) returning true, or false and a message. Failures point at this line.
---@param args Scenario_expect_args
function Scenario:expect(args) end

---Calls fn(frame) after every frame: read displacements, move tools, change loads, stop the run. Errors end the run (outputs are kept, summary marks the error).
---@param fn function function(frame)
function Scenario:on_frame(fn) end

---Evaluates a selection on the mesh now: sorted 0-based node ids (an error at this line when empty).
---@param sel Selection selection
---@return integer[]
function Scenario:select(sel) end

---Every node used by a tet.
---@return Selection
function softcut.select.all() end

---Nodes of the tets with a label.
---@param label integer mesh label
---@return Selection
function softcut.select.label(label) end

---Boundary nodes of the whole body, or of the tets with `label`.
---@param label integer? mesh label (default: whole body)
---@return Selection
function softcut.select.surface(label) end

---@class softcut_select_sphere_args
---@field center number[] center (m)
---@field radius number radius (m)
---Nodes within a ball.
---@param args softcut_select_sphere_args
---@return Selection
function softcut.select.sphere(args) end

---@class softcut_select_box_args
---@field min number[] lower corner (m)
---@field max number[] upper corner (m)
---Nodes in an axis-aligned box (inclusive).
---@param args softcut_select_box_args
---@return Selection
function softcut.select.box(args) end

---@class softcut_select_halfspace_args
---@field point number[] a point on the plane (m)
---@field normal number[] points into the half-space (any length > 0)
---Nodes with (x - point) . normal >= 0.
---@param args softcut_select_halfspace_args
---@return Selection
function softcut.select.halfspace(args) end

---Explicit 0-based node ids (as in the mesh file and the CSV).
---@param ids integer[] node ids
---@return Selection
function softcut.select.nodes(ids) end

---A node set the mesh provides: "hole" of the tube / upper_leg generator; a generated organ's landmarks (liver: right_lobe, left_lobe, underside, dome, lesion; kidney: hilum, convex, upper_pole, lower_pole, underside, top; knee_ligament: tibial, femoral; docs/meshing.md).
---@param name string set name
---@return Selection
function softcut.select.named(name) end

---Nodes in either (also `a + b`).
---@param other Selection other set
---@return Selection
function Selection:union(other) end

---Nodes in both (also `a * b`).
---@param other Selection other set
---@return Selection
function Selection:intersection(other) end

---Nodes in this set and not the other (also `a - b`).
---@param other Selection other set
---@return Selection
function Selection:difference(other) end

---The same value at every time.
---@param value number value
---@return Ramp|number
function softcut.ramp.constant(value) end

---@class softcut_ramp_linear_args
---@field t0? number start (s)
---@field t1 number end (> t0) (s)
---@field from? number value before t0
---@field to? number value from t1 on
---`from` until t0, straight line to `to` at t1, then `to`.
---@param args softcut_ramp_linear_args
---@return Ramp|number
function softcut.ramp.linear(args) end

---@class softcut_ramp_smoothstep_args
---@field t0? number start (s)
---@field t1 number end (> t0) (s)
---@field from? number value before t0
---@field to? number value from t1 on
---Like linear, with zero slope at both ends (3s^2 - 2s^3).
---@param args softcut_ramp_smoothstep_args
---@return Ramp|number
function softcut.ramp.smoothstep(args) end

---@class softcut_ramp_keyframes_args
---@field times number[] key times, strictly increasing (s)
---@field values number[] key values, as many as times
---Piecewise linear through (times[k], values[k]); held before the first and after the last key.
---@param args softcut_ramp_keyframes_args
---@return Ramp|number
function softcut.ramp.keyframes(args) end

---@class softcut_ramp_sine_args
---@field amplitude number amplitude
---@field frequency number frequency (Hz)
---@field phase? number phase (rad)
---@field offset? number mean value
---@field t0? number start (s)
---offset + amplitude * sin(2 pi frequency (t - t0) + phase) from t0; offset before.
---@param args softcut_ramp_sine_args
---@return Ramp|number
function softcut.ramp.sine(args) end

---Value at time t (the engine's evaluation).
---@param t number time (s)
---@return number
function Ramp:at(t) end

---A tool that stays at one point.
---@param point number[] position (m)
---@return Path|number[]
function softcut.path.fixed(point) end

---@class softcut_path_polyline_args
---@field times number[] key times, strictly increasing (s)
---@field points number[][] key points, as many as times (m)
---Straight segments between keyed points, constant speed on each; held before the first and after the last key.
---@param args softcut_path_polyline_args
---@return Path|number[]
function softcut.path.polyline(args) end

---@class softcut_path_catmull_rom_args
---@field times number[] key times, strictly increasing (s)
---@field points number[][] key points, as many as times (m)
---A C1 curve through every keyed point at its time.
---@param args softcut_path_catmull_rom_args
---@return Path|number[]
function softcut.path.catmull_rom(args) end

---@class softcut_path_arc_args
---@field center number[] a point on the rotation axis (m)
---@field axis? number[] rotation axis (right-hand rule; any length > 0)
---@field start number[] position at t0 (m)
---@field sweep number total angle (rad)
---@field t0? number start time (s)
---@field t1 number end time (> t0) (s)
---`start` rotated about the axis through `center` by an angle growing linearly from 0 at t0 to `sweep` at t1.
---@param args softcut_path_arc_args
---@return Path|number[]
function softcut.path.arc(args) end

---Position at time t (the engine's evaluation).
---@param t number time (s)
---@return number[]
function Path:at(t) end

---a + b.
---@param a number[] 
---@param b number[] 
---@return number[]
function softcut.vec.add(a, b) end

---a - b.
---@param a number[] 
---@param b number[] 
---@return number[]
function softcut.vec.sub(a, b) end

---k a.
---@param a number[] 
---@param k number 
---@return number[]
function softcut.vec.scale(a, k) end

---a . b.
---@param a number[] 
---@param b number[] 
---@return number
function softcut.vec.dot(a, b) end

---a x b.
---@param a number[] 
---@param b number[] 
---@return number[]
function softcut.vec.cross(a, b) end

---|a|.
---@param a number[] 
---@return number
function softcut.vec.length(a) end

---a + s (b - a).
---@param a number[] 
---@param b number[] 
---@param s number 
---@return number[]
function softcut.vec.lerp(a, b, s) end

---Displacement of a node (0-based id) this frame; nodes made by cutting have ids after the rest mesh's. Nodes inside the nonoperational region are solved only when logged (s:output{ log = ... }), exported or under an expectation's bounds; reading one otherwise is an error (here and in the other Frame node reads).
---@param node integer node id
---@return number[]
function Frame:displacement(node) end

---Deformed position of a node this frame.
---@param node integer node id
---@return number[]
function Frame:position(node) end

---Mean displacement vector of a node set.
---@param nodes Selection node set
---@return number[]
function Frame:mean_displacement(nodes) end

---Largest displacement magnitude over a node set.
---@param nodes Selection node set
---@return number
function Frame:max_displacement(nodes) end

---A tool's state: tip (vec3, m), engaged (boolean), num_nodes (the nodes it acts on: a grip's are its triangles' corners), force (vec3 {x, y, z}, N: the total force the tool applies to the tissue; its magnitude is softcut.vec.length(force)), pressure (Pa: a scalpel's contact pressure, else 0) and cutting (a scalpel cut this frame).
---@param name string tool name
---@return table
function Frame:tool(name) end

---Cutting so far: events (frames in which a blade changed the mesh), nodes_added, nodes, tets (of the current mesh), faces_separated (faces the blades opened, all events), faces_pending (faces on the cut still joined now: the cut front), components (pieces joined through shared nodes), pieces (rigid pieces: joined through shared faces, so a piece hanging by an edge counts apart), detached (pieces cut free and held). A cut through the section shows as components > 1.
---@return table
function Frame:cutting() end

---Places a tool's tip for the next frames (overrides its path); nil returns it to the path.
---@param name string tool name
---@param point number[]? tip position (m)
function Frame:move_tool(name, point) end

---Switches a tool on or off (a grasper lets go when off).
---@param name string tool name
---@param on boolean on
function Frame:enable_tool(name, on) end

---@class Frame_set_load_args
---@field scale? number multiplies the load's force
---@field enabled? boolean on or off
---Changes a load from the next frame: scale multiplies its ramp, enabled switches it.
---@param name string load name
---@param args Frame_set_load_args
function Frame:set_load(name, args) end

---Ends the run after this frame (summary: stopped).
function Frame:stop() end

---Records a named number this frame (a jaw's force, a gap, a volume): summary.json `metrics` keeps its last value (and frame, time), min, max, mean and samples; softcut sweep gives it the column metric.<name> (the last value). Call it every frame or once at the end; a run records at most 256 names.
---@param name string 1 to 64 letters, digits, _ . or -, starting with a letter or _
---@param value number a finite number, in the unit the name says
function Frame:record(name, value) end
