-- Small helpers for English sentences, loaded with require("words").
local words = {}

-- Trims and drops a leading "my"/"the".
function words.clean(text)
  text = (text or ""):lower():gsub("^%s+", ""):gsub("%s+$", "")
  text = text:gsub("^my%s+", "")
  return text
end

-- Crude but friendly: "keys", "glasses" are plural; "glass", "dress" are not.
function words.plural(item)
  return item:find("s$") ~= nil and item:find("ss$") == nil
end

function words.is_are(item) return words.plural(item) and "are" or "is" end
function words.was_were(item) return words.plural(item) and "were" or "was" end
function words.it_them(item) return words.plural(item) and "them" or "it" end

local PREPOSITIONS = {"next to", "behind", "beside", "under", "in", "on", "at"}

-- The preposition right before `place` in `sentence` ("... in the drawer" -> "in").
function words.preposition_before(sentence, place)
  sentence = sentence:lower()
  local at = sentence:find(place, 1, true)
  if not at then return nil end
  local before = sentence:sub(1, at - 1):gsub("%s+$", "")
  for _, p in ipairs(PREPOSITIONS) do
    if before:sub(-#p) == p then return p end
  end
  return nil
end

return words
