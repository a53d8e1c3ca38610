// The rayset's order: rays sorted by the direction they leave in (see rayset_order.comp).
#ifndef FIRD_DIRECTION_BUCKET_GLSL
#define FIRD_DIRECTION_BUCKET_GLSL

// Spreads the low 16 bits of x to the even bits (Morton order).
uint spread_bits(uint x) {
    x &= 0xffffu;
    x = (x | (x << 8u)) & 0x00ff00ffu;
    x = (x | (x << 4u)) & 0x0f0f0f0fu;
    x = (x | (x << 2u)) & 0x33333333u;
    x = (x | (x << 1u)) & 0x55555555u;
    return x;
}

// The direction's cell on the octahedral map (the unit sphere unfolded onto a square),
// numbered along a Morton curve so that neighbouring buckets hold neighbouring directions.
uint direction_bucket(vec3 d) {
    vec2 p = d.xy / (abs(d.x) + abs(d.y) + abs(d.z));
    if (d.z < 0.0) p = (1.0 - abs(p.yx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
    const float cells = float(1u << kRaysetOrderBits);
    const uvec2 q = uvec2(clamp((p * 0.5 + 0.5) * cells, vec2(0.0), vec2(cells - 1.0)));
    return spread_bits(q.x) | (spread_bits(q.y) << 1u);
}

// Rays leaving the reflector after a bounce: where they start (a 16 x 16 grid over the
// holder), then their direction (16 x 16 octahedral cells).
uint reflected_bucket(vec3 o, vec3 d) {
    const vec2 f = (o.xy - holder_min().xy) / (holder_max().xy - holder_min().xy);
    const uvec2 qo = uvec2(clamp(f * 16.0, vec2(0.0), vec2(15.0)));
    return ((spread_bits(qo.x) | (spread_bits(qo.y) << 1u)) << 8u) | (direction_bucket(d) >> 8u);
}

#endif
