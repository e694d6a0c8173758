// mipcast piece: amip_average_missing
// fills: BinaryMask::Dec
// mode: augment
// Installed only while the analytic average's input holds missing values
// (its MISSING_PIECE): turns on amip_average_hooks' covered-part search
// (BinaryMask::Dec comes before the hooks' Picking::Dec; the exact average
// has no mask, and global_phase, the other piece of this slot, belongs to
// the sampled loop).
#define MC_AVERAGE_MISSING
