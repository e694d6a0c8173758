// mipcast piece: refusal
// fills: Terminate::Init
// mode: augment
// VTK's ray set-up, then mipcast's refusal test (mcRefuseIfAsked, mip_globals).
  mcRefuseIfAsked();
