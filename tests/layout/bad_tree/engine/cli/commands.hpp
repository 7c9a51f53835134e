#pragma once
// A deliberately broken tree for the layer test: the program inside engine/.
