#include "imgui_sdl.hpp"

#include <facet/error.hpp>

#include <imgui.h>

#include <algorithm>

namespace facet::view {

namespace {

int button_index(Uint8 sdl_button) {
    switch (sdl_button) {
        case SDL_BUTTON_LEFT: return 0;
        case SDL_BUTTON_RIGHT: return 1;
        case SDL_BUTTON_MIDDLE: return 2;
        case SDL_BUTTON_X1: return 3;
        case SDL_BUTTON_X2: return 4;
        default: return -1;
    }
}

}  // namespace

ImGuiSdl::ImGuiSdl(SDL_Window* window, SDL_Renderer* renderer)
    : window_(window), renderer_(renderer), context_(ImGui::CreateContext()) {
    ImGui::SetCurrentContext(context_);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // the layout is not saved into the working folder
    io.BackendPlatformName = "facet-view (SDL2)";
    io.BackendRendererName = "facet-view (SDL_Renderer)";
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    const std::pair<ImGuiKey, SDL_Scancode> keys[] = {
        {ImGuiKey_Tab, SDL_SCANCODE_TAB},          {ImGuiKey_LeftArrow, SDL_SCANCODE_LEFT},
        {ImGuiKey_RightArrow, SDL_SCANCODE_RIGHT}, {ImGuiKey_UpArrow, SDL_SCANCODE_UP},
        {ImGuiKey_DownArrow, SDL_SCANCODE_DOWN},   {ImGuiKey_PageUp, SDL_SCANCODE_PAGEUP},
        {ImGuiKey_PageDown, SDL_SCANCODE_PAGEDOWN}, {ImGuiKey_Home, SDL_SCANCODE_HOME},
        {ImGuiKey_End, SDL_SCANCODE_END},          {ImGuiKey_Insert, SDL_SCANCODE_INSERT},
        {ImGuiKey_Delete, SDL_SCANCODE_DELETE},    {ImGuiKey_Backspace, SDL_SCANCODE_BACKSPACE},
        {ImGuiKey_Space, SDL_SCANCODE_SPACE},      {ImGuiKey_Enter, SDL_SCANCODE_RETURN},
        {ImGuiKey_Escape, SDL_SCANCODE_ESCAPE},    {ImGuiKey_KeyPadEnter, SDL_SCANCODE_KP_ENTER},
        {ImGuiKey_A, SDL_SCANCODE_A},              {ImGuiKey_C, SDL_SCANCODE_C},
        {ImGuiKey_V, SDL_SCANCODE_V},              {ImGuiKey_X, SDL_SCANCODE_X},
        {ImGuiKey_Y, SDL_SCANCODE_Y},              {ImGuiKey_Z, SDL_SCANCODE_Z}};
    for (const auto& [key, scancode] : keys) io.KeyMap[key] = scancode;

    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    font_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STATIC, w, h);
    if (!font_) {
        ImGui::DestroyContext(context_);
        throw Error(ErrorCode::display_failed, std::string("ImGui's font: ") + SDL_GetError());
    }
    SDL_UpdateTexture(font_, nullptr, pixels, w * 4);
    SDL_SetTextureBlendMode(font_, SDL_BLENDMODE_BLEND);
    SDL_SetTextureScaleMode(font_, SDL_ScaleModeLinear);
    io.Fonts->SetTexID(font_);
    last_ = SDL_GetPerformanceCounter();
}

ImGuiSdl::~ImGuiSdl() {
    ImGui::DestroyContext(context_);
    if (font_) SDL_DestroyTexture(font_);
}

bool ImGuiSdl::handle(const SDL_Event& e) {
    ImGui::SetCurrentContext(context_);
    ImGuiIO& io = ImGui::GetIO();
    switch (e.type) {
        case SDL_MOUSEMOTION:
            io.MousePos = ImVec2(float(e.motion.x), float(e.motion.y));
            return io.WantCaptureMouse;
        case SDL_MOUSEBUTTONDOWN:
        case SDL_MOUSEBUTTONUP: {
            io.MousePos = ImVec2(float(e.button.x), float(e.button.y));
            const int b = button_index(e.button.button);
            if (b < 0) return io.WantCaptureMouse;
            held_[size_t(b)] = e.type == SDL_MOUSEBUTTONDOWN;
            if (held_[size_t(b)]) pressed_[size_t(b)] = true;
            return io.WantCaptureMouse;
        }
        case SDL_MOUSEWHEEL:
            io.MouseWheel += float(e.wheel.y);
            io.MouseWheelH += float(e.wheel.x);
            return io.WantCaptureMouse;
        case SDL_TEXTINPUT:
            io.AddInputCharactersUTF8(e.text.text);
            return io.WantCaptureKeyboard;
        case SDL_KEYDOWN:
        case SDL_KEYUP: {
            const int scancode = e.key.keysym.scancode;
            if (scancode >= 0 && scancode < int(IM_ARRAYSIZE(io.KeysDown)))
                io.KeysDown[scancode] = e.type == SDL_KEYDOWN;
            const Uint16 mod = e.key.keysym.mod;
            io.KeyShift = mod & KMOD_SHIFT;
            io.KeyCtrl = mod & KMOD_CTRL;
            io.KeyAlt = mod & KMOD_ALT;
            io.KeySuper = mod & KMOD_GUI;
            return io.WantCaptureKeyboard;
        }
        case SDL_WINDOWEVENT:
            if (e.window.event == SDL_WINDOWEVENT_LEAVE) io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
            return false;
        default: return false;
    }
}

void ImGuiSdl::new_frame() {
    ImGui::SetCurrentContext(context_);
    ImGuiIO& io = ImGui::GetIO();
    int w = 0, h = 0, pw = 0, ph = 0;
    SDL_GetWindowSize(window_, &w, &h);
    SDL_GetRendererOutputSize(renderer_, &pw, &ph);
    io.DisplaySize = ImVec2(float(std::max(w, 1)), float(std::max(h, 1)));
    io.DisplayFramebufferScale = ImVec2(float(pw) / float(std::max(w, 1)), float(ph) / float(std::max(h, 1)));
    const uint64_t now = SDL_GetPerformanceCounter();
    io.DeltaTime = std::max(1e-4f, float(double(now - last_) / double(SDL_GetPerformanceFrequency())));
    last_ = now;
    release_pending_ = false;
    for (size_t b = 0; b < held_.size(); ++b) {
        io.MouseDown[b] = held_[b] || pressed_[b];
        release_pending_ = release_pending_ || (pressed_[b] && !held_[b]);
        pressed_[b] = false;
    }
    ImGui::NewFrame();
}

void ImGuiSdl::render() {
    ImGui::SetCurrentContext(context_);
    ImGui::Render();
    const ImDrawData* data = ImGui::GetDrawData();
    const ImVec2 scale = data->FramebufferScale;
    SDL_RenderSetScale(renderer_, scale.x, scale.y);
    for (int n = 0; n < data->CmdListsCount; ++n) {
        const ImDrawList* list = data->CmdLists[n];
        const ImDrawVert* vertices = list->VtxBuffer.Data;
        for (const ImDrawCmd& cmd : list->CmdBuffer) {
            if (cmd.UserCallback) {
                cmd.UserCallback(list, &cmd);
                continue;
            }
            const ImVec2 at = data->DisplayPos;
            const SDL_Rect clip{int(cmd.ClipRect.x - at.x), int(cmd.ClipRect.y - at.y),
                                int(cmd.ClipRect.z - cmd.ClipRect.x),
                                int(cmd.ClipRect.w - cmd.ClipRect.y)};
            if (clip.w <= 0 || clip.h <= 0) continue;
            SDL_RenderSetClipRect(renderer_, &clip);
            const ImDrawVert* v = vertices + cmd.VtxOffset;
            const int stride = int(sizeof(ImDrawVert));
            SDL_RenderGeometryRaw(renderer_, static_cast<SDL_Texture*>(cmd.GetTexID()), &v->pos.x,
                                  stride, reinterpret_cast<const SDL_Color*>(&v->col), stride,
                                  &v->uv.x, stride, list->VtxBuffer.Size - int(cmd.VtxOffset),
                                  list->IdxBuffer.Data + cmd.IdxOffset, int(cmd.ElemCount),
                                  int(sizeof(ImDrawIdx)));
        }
    }
    SDL_RenderSetClipRect(renderer_, nullptr);
    SDL_RenderSetScale(renderer_, 1.0f, 1.0f);
}

}  // namespace facet::view
