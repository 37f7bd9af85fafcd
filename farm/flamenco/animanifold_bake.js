// SPDX-License-Identifier: MIT
//
// Flamenco 3 custom job type: the animanifold farm bake (chunks, then assemble), calling the
// same shipped entry point as farm/openjd/bake/template.yaml (the add-on's farm module).
// Copy this file into the Flamenco Manager's `scripts/` folder and restart the Manager; the job
// type appears in the Flamenco add-on's submit panel as "Animanifold Bake".
//
// This is a documented example: it is not run by the project's tests (no Flamenco Manager is
// available where they run). The workers need the Animanifold add-on enabled in their Blender.

const JOB_TYPE = {
  label: "Animanifold Bake",
  description: "Bake manifold objects in frame chunks, then assemble one .blend and one Alembic",
  settings: [
    { key: "frames", type: "string", required: true,
      eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
      description: "Frame range to bake, e.g. '1-250'" },
    { key: "chunk_size", type: "int32", default: 50, description: "Frames per bake task" },
    { key: "object", type: "string", default: "", description: "One manifold object (empty: all)" },
    { key: "chunk_outputs", type: "string", default: "blend,obj",
      description: "Per chunk: blend (needed by assemble), abc, obj, ply" },
    { key: "output_dir", type: "string", subtype: "dir_path", required: true,
      eval: "'//animanifold_farm/'", description: "Shared folder for chunks and the assembly" },
    { key: "blendfile", type: "string", required: true, visible: "web",
      description: "The .blend with the converted manifold object(s)" },
  ],
};

const FARM_EXPR = "from animanifold_blender import farm; farm.main()";

function farmCommand(settings, farmArgs) {
  return author.Command("blender-render", {
    exe: "{blender}",
    exeArgs: "{blenderArgs}",
    argsBefore: [],
    blendfile: settings.blendfile,
    args: ["--python-exit-code", "1", "--python-expr", FARM_EXPR, "--"].concat(farmArgs),
  });
}

function compileJob(job) {
  const settings = job.settings;
  const [first, last] = settings.frames.split("-").map((f) => parseInt(f, 10));
  const bakeTasks = [];
  for (let start = first; start <= last; start += settings.chunk_size) {
    const task = author.Task(`bake-${start}`, "blender");
    task.addCommand(farmCommand(settings, [
      "bake-chunk", "--start", String(start), "--end", String(last),
      "--chunk-size", String(settings.chunk_size), "--outputs", settings.chunk_outputs,
      "--directory", settings.output_dir, "--object", settings.object,
    ]));
    job.addTask(task);
    bakeTasks.push(task);
  }
  const assemble = author.Task("assemble", "blender");
  assemble.addCommand(farmCommand(settings, [
    "assemble", "--directory", settings.output_dir, "--object", settings.object, "--outputs", "blend,abc",
  ]));
  for (const task of bakeTasks) assemble.addDependency(task);
  job.addTask(assemble);
}
