// Nori 2's gui.h names its OpenGL window (NoriScreen). This renderer shows a render in a
// web browser instead (`nori --preview`, docs/user-guide.md), so the header is here only
// so that course files including it compile; it declares nothing.
#pragma once

#include <nori/common.h>
