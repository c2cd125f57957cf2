#pragma once
// Mesh files for the hostile-input tests (issue 32), made at test time: a 3MF package whose
// relationship points at a missing model part (Debian's assimp aborts on an ai_assert), and a
// 141-byte DirectX .x file declaring 250 million vertices.
#include <cstdlib>
#include <fstream>
#include <string>

namespace taskmap::testing {

/// Writes the 3MF with /usr/bin/python3's zipfile; false when python failed.
inline bool writeMissingPart3mf(const std::string& path) {
  const std::string script = path + ".py";
  std::ofstream(script) << R"PY(import sys, zipfile
with zipfile.ZipFile(sys.argv[1], "w") as z:
    z.writestr("[Content_Types].xml", '<?xml version="1.0" encoding="UTF-8"?>'
        '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
        '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
        '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
        '</Types>')
    z.writestr("_rels/.rels", '<?xml version="1.0" encoding="UTF-8"?>'
        '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
        '<Relationship Target="/3D/missing.model" Id="rel0" '
        'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>')
)PY";
  const int rc = std::system((std::string(TASKMAP_PYTHON) + " " + script + " " + path).c_str());
  std::remove(script.c_str());
  return rc == 0;
}

/// A DirectX .x text file declaring `vertices` vertices and holding one.
inline void writeHugeDeclarationX(const std::string& path,
                                  const std::string& vertices = "250000000") {
  std::ofstream(path, std::ios::binary)
      << "xof 0302txt 0064\nMesh {\n " << vertices << ";\n 0.0;0.0;0.0;;\n 1;\n 3;0,0,0;;\n}\n";
}

}  // namespace taskmap::testing
