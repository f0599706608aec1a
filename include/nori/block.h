// Nori 2's name for the image block header: course code that includes <nori/block.h>
// gets the ImageBlock of imageblock.h. (Nori 2's BlockGenerator is not provided: the
// render loop, render.h, hands out the blocks.)
#pragma once

#include <nori/imageblock.h>
